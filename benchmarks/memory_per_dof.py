"""Peak memory of a case against its DOF: the constants of the cost guard (capslide.model.cost).

Runs short cases (approach, preload, a slide to ubar = 0.3 L0, no snapshots) at several mesh sizes, one process
each, and prints a Markdown table of peak resident memory (ru_maxrss), DOF and bytes per DOF above the interpreter's
own footprint (the first row's run with the smallest mesh gives the base).

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/memory_per_dof.py [--variant Q1:8 Q1:4 Q2:16 ...]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

CONFIG = Path(__file__).resolve().parents[1] / "config" / "config.yaml"
PROBE = ("import resource, sys; from capslide.cli import main; code = main(sys.argv[1:]); "
         "print('MAXRSS_KB', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)")


def peak(element: str, size: str, out: Path) -> tuple[int, float]:
    args = [str(CONFIG), "--set", "preset=fast", "--set", f"mesh.element={element}", "--set", f"mesh.size={size}",
            "--set", "loading.ubar_max=0.3", "--set", "output.snapshot_ubar=[]", "--set", "output.checkpoint_every=0"]
    res = subprocess.run([sys.executable, "-c", PROBE, "run", *args, "-q", "-o", str(out)], capture_output=True,
                         text=True)
    kb = int(next(line.split()[1] for line in res.stderr.splitlines() if line.startswith("MAXRSS_KB")))
    from capslide.config import load_config
    from capslide.fem.mesh import cell_and_node_counts
    from capslide.model.build import cap_mesh_spec
    from capslide.params import Parameters

    p = Parameters.from_config(load_config([CONFIG], args[2::2]))
    _, nodes = cell_and_node_counts(cap_mesh_spec(p))
    return 2 * nodes, kb * 1024.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variant", nargs="+", default=["Q1:32", "Q1:8", "Q1:4", "Q1:2", "Q2:16", "Q2:8", "Q2:4"])
    ap.add_argument("--out", type=Path, default=Path("/tmp/capslide_memory.nc"))
    a = ap.parse_args()
    rows = [(v, *peak(*v.split(":"), a.out)) for v in a.variant]
    base = min(m for _, _, m in rows)
    print("| element:mesh.size | DOF | peak memory (MB) | bytes per DOF above the smallest run |")
    print("|---|---|---|---|")
    for v, dofs, m in rows:
        print(f"| {v} | {dofs:,} | {m / 1e6:.0f} | {(m - base) / dofs:.0f} |")


if __name__ == "__main__":
    main()
