"""The adhesive sphere's load against its approach: a `capslide verify` sweep against its law on a half-space, with
no contact radius read.

P(a), the issue's measure, needs the FE's contact radius, read from a mesh (docs/three_d.md, "Why the level
radius"). The approach delta needs none: delta = H - h, h the rigid flat's height over the clamped base (the log's
`h=`), against the same law's half-space path (capslide.studies.halfspace_sphere, the sphere's profile) at the same
load. The FE body is a clamped cap, not a half-space: it is stiffer by a compliance c (L0 per E L0^2) that a
half-space's far field would add. c is computed here, not fitted: a linear solve of the scene's mesh at rest (the
base clamped, the symmetry plane held) under Hertz's pressure on a disc of the FE's contact radius, whose apex
moves by c P less than a half-space's, 3 P / (4 b E*) (Johnson 1985, section 3.4, with P = 2/3 pi p0 b^2). At zero
load c drops out. At the FE's approach, corrected by c P, the law carries P + (dP/ddelta) (delta_FE + c P - delta_law);
the table gives P_FE - P_law at the same approach, relative to the law's |P_c| ("+": the FE less tensile, as in
docs/three_d.md's P - P_law(a)). Loads P = -Fn, compressive positive (E L0^2); lengths L0.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/sphere_load_approach.py --scene sphere_dugdale3 --log LOG
        [--set KEY=VALUE ...]   (LOG: the `capslide verify` log, e.g. logs/paper/verification3d/sphere_dugdale3.log)
"""

from __future__ import annotations

import argparse
import re

import numpy as np

from capslide.config import load_config, scene_path
from capslide.fem.assembly import BulkForm, Dirichlet, rigid_body_modes
from capslide.laws import analytic
from capslide.model.build import mesh_of
from capslide.params import Parameters
from capslide.solvers.amg import SETTINGS, AMGSolver
from capslide.studies.halfspace_sphere import halfspace_of, pull_off, reference_radii

LINE = re.compile(r"preload\s+ubar=.*h=\s*([+-]?[\d.]+)\s+Fn=([+-][\d.]+).*area=\s*([\d.]+)")


def sweep_loads(log: str) -> list[tuple[float, float, float]]:
    """(P, h, contact radius sqrt(area / pi)) of each force-controlled equilibrium (`preload` line) of a log, once
    each (a resumed run logs its checkpointed loads again)."""
    out = {}
    for line in open(log):
        m = LINE.match(line)
        if m:
            out[m.group(2)] = (-float(m.group(2)), float(m.group(1)), float(np.sqrt(float(m.group(3)) / np.pi)))
    return list(out.values())


def face_loads(nodes: np.ndarray, faces: np.ndarray, pressure) -> np.ndarray:
    """Nodal z-forces (downward, per node) of a pressure p(r) on the top's quadrilateral faces, each face's
    p(centroid) x area shared by its four corners."""
    x = nodes[faces[:, :4]]
    area = 0.5 * (np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1)
                  + np.linalg.norm(np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 0]), axis=1))
    share = pressure(np.linalg.norm(x.mean(axis=1)[:, :2], axis=1)) * area / 4.0
    f = np.zeros(len(nodes))
    np.add.at(f, faces[:, :4].ravel(), np.repeat(share, 4))
    return f


def body_compliance(params: Parameters, radii: list[float]) -> list[float]:
    """c (L0 per E L0^2) at each Hertz radius b: the half-space's apex displacement under a unit load of Hertz's
    pressure on a disc of radius b, less the clamped cap's (the scene's mesh, linear, at rest, in units of E)."""
    mesh = mesh_of(params)
    nu = params.material.nu
    form = BulkForm(mesh, nu / ((1 + nu) * (1 - 2 * nu)), 1.0 / (2 * (1 + nu)))
    _, data = form.residual_and_tangent_data(np.zeros(mesh.n_dofs))
    fixed = np.union1d(np.concatenate([3 * mesh.base + i for i in range(3)]), 3 * mesh.symmetry + 1)
    bc = Dirichlet.on_dofs(fixed, form.pattern)
    rhs = []
    for b in radii:  # Hertz's shape, scaled to P = 1 on the whole disc: the half model's faces carry half of it
        f = face_loads(mesh.nodes, mesh.surface_segments, lambda r, b=b: np.sqrt(np.clip(1.0 - (r / b) ** 2, 0.0, None)))
        rhs.append(np.zeros(mesh.n_dofs))
        rhs[-1][2::3] = -0.5 * f / f.sum()
    B = np.column_stack(rhs)
    bc.apply(data)
    B[bc.dofs] = 0.0
    A = form.pattern.matrix(data)
    solver = AMGSolver(near_null_space=rigid_body_modes(mesh.nodes), options=dict(SETTINGS), cycle="W",
                       block_size=3, rtol=1e-10, maxiter=2000, symmetric=True)
    U, _ = solver.solve(A, B)
    top = np.unique(mesh.surface_segments)
    apex = top[np.argmin(np.linalg.norm(mesh.nodes[top, :2], axis=1))]
    E_star = analytic.effective_modulus(1.0, nu)
    return [3.0 / (4.0 * b * E_star) + float(U.reshape(len(B), -1)[3 * apex + 2, k]) for k, b in enumerate(radii)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="sphere_dugdale3")
    ap.add_argument("--log", required=True)
    ap.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args()
    params = Parameters.from_config(load_config([scene_path(args.scene)], args.overrides))
    loads = sweep_loads(args.log)
    halfspace = halfspace_of(params)
    path = halfspace.edge_path(reference_radii(params, 1.03 * max(a for *_, a in loads)))
    P_c, a_c = pull_off(path)
    stable = [s for s in path if s.a > a_c]
    P, delta = np.array([s.P for s in stable]), np.array([s.delta for s in stable])
    stiffness = np.gradient(P, delta)
    c = body_compliance(params, [a for *_, a in loads])
    print(f"{args.scene}: the law's pull-off {P_c:.4f} E L0^2 at a = {a_c:.3f} L0; H = {params.geometry.H:g} L0")
    print("| P (E L0^2) | a, FE (L0) | delta, FE (L0) | delta, law | difference | c P (the body) | "
          "dP/ddelta, law (E L0) | P - P_law at the same approach, of \\|P_c\\| |")
    print("|---" * 8 + "|")
    for (load, h, a), ck in zip(loads, c):
        d_fe, d_law, k = params.geometry.H - h, np.interp(load, P, delta), np.interp(load, P, stiffness)
        err = -k * (d_fe + ck * load - d_law) / abs(P_c)
        print(f"| {load:+.1f} | {a:.3f} | {d_fe:.5f} | {d_law:.5f} | {d_fe - d_law:+.5f} | {ck * load:+.5f} "
              f"| {k:.2f} | {err:+.2%} |")


if __name__ == "__main__":
    main()
