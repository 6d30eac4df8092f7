"""The graded H1 half model of the spherical cap: cells, DOF, shape and volume at several surface cell sizes h0.

The `sphere` scene's cap (R = 47.1 L0, H = 10 L0, band radius 9 L0). Per h0: cells and DOF (from the plan, equal
to the mesh's), the largest and the 99th percentile of the cells' aspect ratio (longest over shortest edge), the
largest facet edge in the band over h0, the smallest Jacobian at the cells' corners, twice the half model's volume
against the cap's, and the time to build.

    .venv/bin/python benchmarks/sphere_mesh.py --h0 0.6 0.3 0.15 0.1
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from capslide.fem.hex_mesh import SphereCapSpec, sphere_cap_counts, sphere_cap_mesh, spherical_cap_volume

EDGES = ([0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 2, 3], [1, 2, 3, 0, 5, 6, 7, 4, 4, 5, 6, 7])  # the hexahedron's 12 edges


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h0", type=float, nargs="+", default=[0.6, 0.3, 0.15, 0.1])
    ap.add_argument("--band", type=float, default=9.0)
    args = ap.parse_args()
    corners = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)], dtype=float)
    print("| h0 (L0) | cells | DOF | layers | aspect ratio, max | p99 | band edge / h0 | min corner Jacobian "
          "| volume error | build (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for h0 in args.h0:
        spec = SphereCapSpec(R=47.1, H=10.0, h0=h0, band_radius=args.band)
        t = time.perf_counter()
        mesh = sphere_cap_mesh(spec)
        elapsed = time.perf_counter() - t
        assert sphere_cap_counts(spec) == (mesh.n_cells, mesh.n_nodes)
        X = mesh.nodes[mesh.cells]
        lengths = np.linalg.norm(X[:, EDGES[1]] - X[:, EDGES[0]], axis=2)
        aspect = lengths.max(axis=1) / lengths.min(axis=1)
        P = mesh.nodes[mesh.surface_segments]
        band = np.linalg.norm(P.mean(axis=1)[:, :2], axis=1) < args.band
        edge = np.linalg.norm(np.roll(P, -1, axis=1) - P, axis=2).max(axis=1)[band].max() / h0
        volume = 2 * mesh.area() / spherical_cap_volume(47.1, 10.0) - 1
        print(f"| {h0:g} | {mesh.n_cells} | {mesh.n_dofs} | {mesh.info['layers']} | {aspect.max():.1f} "
              f"| {np.percentile(aspect, 99):.1f} | {edge:.2f} | {mesh.jacobians(corners).min():.3g} | {volume:+.1e} "
              f"| {elapsed:.2f} |")


if __name__ == "__main__":
    main()
