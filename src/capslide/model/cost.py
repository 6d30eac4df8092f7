"""What a configuration will cost, estimated before anything is computed, and the refusal of what is too much.

Cells and nodes are counted from the mesh spec (:func:`capslide.fem.mesh.cell_and_node_counts`, exact, no mesh
built); peak memory follows from the DOF with the bytes per DOF that ``benchmarks/memory_per_dof.py`` measured;
the least number of steps is every leg's range over its largest step. A configuration beyond ``limits`` is refused
with one line that gives the estimate and the key to raise.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..config import ConfigError
from ..fem.hex_mesh import SphereCapSpec, sphere_cap_counts
from ..fem.mesh import BandTooWide, CapMeshSpec, band_limit, cell_and_node_counts
from ..params import Parameters
from ..solvers.pardiso import mkl_runtime
from .reach import check_preload_area

__all__ = ["Cost", "estimate", "check", "check_steps", "check_factorization", "MEMORY_BASE_GB", "MEMORY_PER_DOF"]

# Measured by benchmarks/memory_per_dof.py (peak resident memory of short cases): the interpreter and libraries, and
# the bytes per DOF above them at the largest measured mesh of each element (they grow slowly with the DOF).
MEMORY_BASE_GB = 0.16
MEMORY_PER_DOF = {"Q1": 4000.0, "Q2": 6500.0}
# H1: benchmarks/amg_sphere.py's peak resident memory over the DOF (a tangent and one AMG setup and solve): 1.6 GB at
# 82k DOF, 8.1 GB at 369k (the sparse pattern's construction is the peak)
MEMORY_PER_DOF["H1"] = 22000.0
# H2: a 27-node cell couples 81 DOF; the sparse pattern has about 2.4 times H1's entries per row
MEMORY_PER_DOF["H2"] = 50000.0


@dataclass(frozen=True)
class Cost:
    cells: int
    dofs: int
    memory_gb: float
    steps: dict[str, int]  # least number of steps per leg, by the key of its largest step

    @property
    def min_steps(self) -> int:
        return sum(self.steps.values())


def _least_steps(p: Parameters) -> dict[str, int]:
    """Least number of steps of each leg, keyed by the config key of its largest step."""
    L = p.loading
    approach = abs(L.approach_start_gap - L.approach_end_gap) / L.approach_step
    force_path = abs(L.preload) if L.preload <= 0 else abs(L.retract_from) + abs(L.preload - L.retract_from)
    slide = abs(L.ubar_max) * (2 if L.slide_back else 1) / L.max_slide_step
    return {"loading.approach_step_over_r0": int(approach), "loading.force_step": int(force_path / L.force_step),
            "loading.max_slide_step": int(slide)}


def estimate(p: Parameters, spec: CapMeshSpec | SphereCapSpec) -> Cost:
    """Cells, DOF, peak memory (GB) and least steps of a case on the cap mesh of ``spec`` (2D, or the 3D sphere's)."""
    if isinstance(spec, SphereCapSpec):
        (cells, nodes), dim, element = sphere_cap_counts(spec), 3, "H2" if spec.order == 2 else "H1"
    else:
        (cells, nodes), dim, element = cell_and_node_counts(spec), 2, spec.element
    dofs = dim * nodes
    memory = MEMORY_BASE_GB + MEMORY_PER_DOF[element] * dofs / 1e9
    return Cost(cells, dofs, memory, _least_steps(p))


def _value(p: Parameters, key: str):
    section, name = key.split(".")
    return p.config[section][name]


def _band_error(p: Parameters, spec: CapMeshSpec | SphereCapSpec, why: str) -> ConfigError:
    """Which key makes the refined contact band too wide for the cap top, in one line."""
    if isinstance(spec, SphereCapSpec):
        key = "mesh.band_half_width" if p.mesh.band_half_width is not None else "geometry.R"
        return ConfigError(f"{key} = {_value(p, key)!r} is not allowed here: {why}")
    room, g = band_limit(spec), p.geometry
    cap = f"the cap top (geometry.R = {g.R:g}, geometry.H = {g.H:g}) has room for a band of {room:.3g} L0"
    if room <= 0.0:
        return ConfigError(f"geometry.H = {_value(p, 'geometry.H')!r} is not allowed here: the cap top (geometry.R = "
                           f"{g.R:g}) has no room for a refined contact band at this mesh.size")
    if p.mesh.band_half_width is not None:
        return ConfigError(f"mesh.band_half_width = {_value(p, 'mesh.band_half_width')!r} is not allowed here: {cap}")
    a0 = spec.band_half_width - abs(p.loading.ubar_max)  # the 2D JKR zero-load half-width
    if a0 > room:
        return ConfigError(f"geometry.R = {_value(p, 'geometry.R')!r} is not allowed here: its 2D JKR contact "
                           f"half-width is {a0:.3g} L0 and {cap}")
    return ConfigError(f"loading.ubar_max = {_value(p, 'loading.ubar_max')!r} is not allowed here: the band covers "
                       f"the contact (half-width {a0:.3g} L0) and the slide, and {cap}")


def check(p: Parameters, spec: CapMeshSpec | SphereCapSpec, steps: bool = True) -> Cost:
    """The estimate, or ConfigError (one line: the estimate and the key to raise) when it exceeds ``limits``, or when
    ``loading.preload_area`` lies beyond what a preload can reach (:func:`capslide.model.reach.check_preload_area`).

    ``steps=False`` checks the mesh alone (``capslide mesh``)."""
    limits = p.limits
    try:
        cost = estimate(p, spec)
    except BandTooWide as e:
        raise _band_error(p, spec, str(e)) from None
    mesh = f"mesh.size = {p.mesh.size!r} ({p.mesh.element}) gives about {cost.cells:,} cells, {cost.dofs:,} DOF"
    if cost.dofs > limits.max_dofs:
        raise ConfigError(f"{mesh}: above limits.max_dofs = {limits.max_dofs:g} (raise it to compute this mesh)")
    if cost.memory_gb > limits.max_memory_gb:
        raise ConfigError(f"{mesh} and needs about {cost.memory_gb:.1f} GB: above limits.max_memory_gb = "
                          f"{limits.max_memory_gb:g} (raise it to compute this mesh)")
    if steps:
        check_steps(p)
        check_factorization(p)
        check_preload_area(p)
    return cost


def check_factorization(p: Parameters) -> None:
    """ConfigError when ``solver.factorization`` names a library this Python environment lacks."""
    if p.solver.factorization == "pardiso" and mkl_runtime() is None:
        raise ConfigError("solver.factorization = 'pardiso' needs Intel MKL's runtime library, which this Python "
                          "environment lacks: pip install mkl (x86-64 only), or use superlu")


def check_steps(p: Parameters) -> None:
    """ConfigError when the least number of steps of the load path exceeds ``limits.max_steps``."""
    least, limit = _least_steps(p), p.limits.max_steps
    if sum(least.values()) > limit:
        key = max(least, key=least.get)
        raise ConfigError(f"{key} = {_value(p, key)!r} needs at least {least[key]:,} steps ({sum(least.values()):,} in "
                          f"all): above limits.max_steps = {limit} (raise it, or the step)")
