"""How much of an adhesive sphere's contact load is the surface quadrature's, at 2, 3, 4, 6 and 8 Gauss points per
face edge (`mesh.surface_gauss_points`) against 24:
- on the same law's exact gap profile (capslide.studies.surface_quadrature: the law's half-space solution at
  contact radii a ring width apart in 16 phases, at each of --radii), the largest error over the phases;
- or, given a CHECKPOINT (a verification sweep's or a case's), on its saved state: the same displacements with
  the contact integrated at 2 and 4 points against 8.

A law with kinks (the Dugdale verification law: its plateau ends at the contact edge, where a stiff repulsion
begins) is integrated only to the point spacing: a point on either side of a kink carries its weight's traction,
so the force moves by whole rings of points as the edge passes them. The finest count is the reference; the
force errors are relative to Maugis-Dugdale's |P_c| (the scene's pull-off reference). Only the state's x is read,
without the code-version check a resume makes.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/surface_quadrature_error.py [CHECKPOINT.npz]
        [--scene sphere_dugdale3] [--set KEY=VALUE ...] [--radii 7 9 11.5 12.4]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from capslide.config import load_config, scene_path
from capslide.io.checkpoint import read_arrays
from capslide.model.build import build_model, mesh_of, mesh_spec
from capslide.params import Parameters
from capslide.studies.surface_quadrature import quadrature_loads
from capslide.studies.verification import pull_off_reference

POINTS = (2, 3, 4, 6, 8, 24)  # per face edge; the last is the reference
PHASES = 16  # contact radii across one ring width


def profile_table(params: Parameters, radii: list[float]) -> None:
    mesh = mesh_of(params)
    spec = mesh_spec(params)
    ring = spec.line_size or spec.h0
    edges = np.concatenate([a + ring * np.arange(PHASES) / PHASES for a in radii])
    loads = quadrature_loads(params, mesh, edges, POINTS)
    P_c = abs(pull_off_reference(params))
    print(f"the law's exact gap profile, contact radii in {PHASES} phases across a ring ({ring:.4g} L0); the largest "
          f"load error against {POINTS[-1]} points per face edge, of Maugis-Dugdale's |P_c| = {P_c:.4f} E L0^2")
    print("| points per face edge | " + " | ".join(f"a = {a:g} L0" for a in radii) + " | mean \\|error\\| |")
    print("|---|" + "---|" * (len(radii) + 1))
    for n in POINTS[:-1]:
        err = np.abs(loads[n] - loads[POINTS[-1]]).reshape(len(radii), PHASES) / P_c
        print(f"| {n} | " + " | ".join(f"{e:.2%}" for e in err.max(axis=1)) + f" | {err.mean():.2%} |")


def checkpoint_table(scene: str, sets: list[str], checkpoint: Path, points: list[int]) -> None:
    x = read_arrays(checkpoint)["x"]
    forces = {}
    for n in points:
        params = Parameters.from_config(load_config([scene_path(scene)], [*sets, f"mesh.surface_gauss_points={n}"]))
        model = build_model(params)
        forces[n] = float(model.contact.force(x[:-1], x[-1], 0.0)[1])
    P_c = abs(pull_off_reference(params))
    finest = forces[max(points)]
    print(f"{checkpoint}: Maugis-Dugdale's |P_c| = {P_c:.4f} E L0^2")
    print("| points per face edge | Fn (E L0^2) | against the finest, of \\|P_c\\| |")
    print("|---|---|---|")
    for n in points:
        print(f"| {n} | {forces[n]:+.5f} | {(forces[n] - finest) / P_c:+.2%} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("checkpoint", type=Path, nargs="?")
    ap.add_argument("--scene", default="sphere_dugdale3")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="the run's --set options")
    ap.add_argument("--radii", type=float, nargs="+", default=[7.0, 9.0, 11.5, 12.4], help="contact radii (L0)")
    args = ap.parse_args()
    if args.checkpoint is None:
        profile_table(Parameters.from_config(load_config([scene_path(args.scene)], args.set)), args.radii)
    else:
        checkpoint_table(args.scene, args.set, args.checkpoint, [2, 4, 8])


if __name__ == "__main__":
    main()
