"""Frozen parameter objects built once from a validated configuration.

This is the one place where physical (SI) values become internal units:
stress in E, length in L0, force per unit width in E L0 (out-of-plane
width W = 1). Everything downstream works in internal units.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .config import SPHERE_ELEMENTS, ConfigError

__all__ = [
    "cgcm_constants",
    "lame_plane_strain",
    "Units",
    "Material",
    "Adhesion",
    "Friction",
    "ContactSpec",
    "Geometry",
    "MeshSpec",
    "Loading",
    "SolverSpec",
    "Output",
    "Limits",
    "Verification",
    "Parameters",
]


def cgcm_constants(T_max: float, W_adh: float) -> dict[str, float]:
    """CGCM constants from (T_max, W_adh), in any consistent units.

    Inverts the paper's relations (Mergel et al. 2019, eqs. Wadh, gmaxTnmax):
    W_adh = 15^(1/3) A_H / (16 pi r0^2), T_max = sqrt(5) A_H / (9 pi r0^3),
    so r0 = (W_adh / T_max) 16 sqrt(5) / (9 15^(1/3)); then
    T0 = A_H / (2 pi r0^3), g_eq = r0 / 15^(1/6), g_max = r0 / 5^(1/6).
    """
    r0 = (W_adh / T_max) * 16.0 * math.sqrt(5.0) / (9.0 * 15.0 ** (1.0 / 3.0))
    A_H = 9.0 * math.pi * r0**3 * T_max / math.sqrt(5.0)
    return {
        "r0": r0,
        "A_H": A_H,
        "T0": A_H / (2.0 * math.pi * r0**3),
        "g_eq": r0 / 15.0 ** (1.0 / 6.0),
        "g_max": r0 / 5.0 ** (1.0 / 6.0),
        "T_max": T_max,
        "W_adh": W_adh,
    }


def lame_plane_strain(E: float, nu: float) -> tuple[float, float]:
    """Lame constants (Lambda, mu) from Young's modulus and Poisson's ratio; Lambda = inf at nu = 0.5."""
    lam = math.inf if nu == 0.5 else E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = E / (2.0 * (1.0 + nu))
    return lam, mu


@dataclass(frozen=True)
class Units:
    """Scales of the internal unit system (SI values)."""

    E: float  # Pa: unit of stress
    L0: float  # m: unit of length

    @property
    def force_per_width(self) -> float:
        """N/m: unit of force per unit out-of-plane width (E L0)."""
        return self.E * self.L0

    @property
    def energy_per_area(self) -> float:
        """J/m^2: unit of work of adhesion (E L0)."""
        return self.E * self.L0


@dataclass(frozen=True)
class Material:
    """Plane-strain neo-Hooke bulk, internal units (E = 1)."""

    E: float
    nu: float
    lam: float
    mu: float  # long-time shear modulus with viscous branches
    prony_g: tuple[float, ...] = ()  # branch shear moduli / mu (material.model = viscoelastic)
    prony_tau: tuple[float, ...] = ()  # branch relaxation times (s)


@dataclass(frozen=True)
class Adhesion:
    """CGCM constants in internal units (stress / E, length / L0)."""

    r0: float
    A_H: float  # E L0^3
    T0: float
    g_eq: float
    g_max: float
    T_max: float
    W_adh: float  # E L0
    g_reg: float
    law: str = "cgcm"  # or "dugdale": its g_max is its contact edge, g_eq + dugdale_penalty W_adh / T_max
    dugdale_ramp: float = 0.8  # units of h0 = W_adh / T_max
    dugdale_penalty: float = 0.005  # units of h0


@dataclass(frozen=True)
class Friction:
    """Friction law parameters in internal units.

    ``g_cut`` is the cut-off of the active model (DI: g_cut_DI, EA:
    s_cut g_max + (1 - s_cut) g_eq; None when frictionless).
    """

    model: str
    tau_DI: float
    g_cut_DI: float
    k_DI: float  # 1 / L0
    mu_EA: float
    s_cut: float
    g_cut_EA: float
    eps_t: float  # E / L0
    DI_area: str = "current"  # DI's threshold per current or per reference area
    static_over_kinetic: float = 1.0  # static threshold / kinetic threshold (the law's)
    slip_weakening_distance: float = 0.1  # L0: slip over which the threshold falls from static to kinetic
    active_from: str = "slide"  # friction acts from the slide on, or from the first contact
    threshold_at: str = "current"  # at the current state, or fixed over a step: step_start, step_predicted

    @property
    def weakening(self) -> tuple[float, float] | None:
        """(static/kinetic, slip-weakening distance) when the static threshold exceeds the kinetic one, else None."""
        return (self.static_over_kinetic, self.slip_weakening_distance) if self.static_over_kinetic > 1.0 else None

    @property
    def g_cut(self) -> float | None:
        return {"DI": self.g_cut_DI, "EA": self.g_cut_EA}.get(self.model)


@dataclass(frozen=True)
class ContactSpec:
    """Contact integral settings in internal units (L0)."""

    far_gap: float
    repulsion_only: bool
    area_gap: float
    normal_traction_area: str = "reference"  # Tn per reference area (theta_k = 1) or per current area (theta_k = J_s)


@dataclass(frozen=True)
class Geometry:
    """Cap geometry (L0)."""

    R: float
    H: float

    @property
    def half_base(self) -> float:
        """Half-width of the flat base: sqrt(H (2R - H))."""
        return math.sqrt(self.H * (2.0 * self.R - self.H))


@dataclass(frozen=True)
class MeshSpec:
    element: str
    size: float
    surface_gauss_points: int
    band_half_width: float | None
    max_size_over_H: float = 0.25
    formulation: str = "displacement"  # or "mixed" (Q2/P1, fem.mixed)
    max_layer_aspect: float | None = None  # 3D: the thickest layer under the band / h0 (fem.hex_mesh)
    symmetry_plane: bool = True  # 3D: the half model (y >= 0) with its plane of symmetry, else the whole cap
    line_band: tuple[float, float] | None = None  # 3D: reference radii (L0) of the annulus refined at the contact line
    line_refinement: float = 4.0  # 3D: h0 / the ring width in that annulus


@dataclass(frozen=True)
class Loading:
    preload: float  # Fn* (E L0 W), positive = tensile
    ubar_max: float  # L0
    approach_start_gap: float  # L0
    approach_end_gap: float  # L0
    approach_step: float  # L0
    approach_edge_step: float  # L0; 0: no edge-controlled spreading stage
    force_step: float  # E L0
    min_force_step: float  # E L0
    retract_from: float  # E L0
    slide_step: float  # L0
    max_slide_step: float  # L0
    min_slide_step: float  # L0
    stop_at_onset: bool = False  # end the slide at the onset of full sliding
    readhesion_snap: str = "end"  # a snap from a peeling to a re-adhered contact: end (detached) or follow
    slide_back: bool = False  # after ubar_max, slide back to ubar = 0
    max_cutbacks: int = 200  # step halvings per load phase before the case is declared diverged
    slide_growth_iterations: int = 4  # a slide step of at most this many Newton iterations lets the next one grow
    preload_via: tuple[float, ...] = ()  # E L0: forces the preload lands on when it passes them
    normal_control: str = "force"  # while sliding: force, height or spring
    spring_stiffness: float | None = None  # E (2D: force per width per length) or E L0 (3D) of normal_control = spring
    velocity: float | None = None  # L0/s: the stage's speed; None: quasi-static, no time
    dwell: float = 0.0  # s: hold at the preload before the slide
    preload_area: float | None = None  # L0^2 (3D) or L0 (2D): the preload's target contact area; None: the force
    preload_area_rtol: float = 1e-3  # relative tolerance of preload_area


@dataclass(frozen=True)
class Output:
    """What a case file holds and how often a case saves a checkpoint (``output``)."""

    snapshot_ubar: tuple[float, ...]  # L0: field snapshots at these slide positions
    checkpoint_every: int  # converged steps between checkpoints (0: none)
    surface_profiles: bool  # per-step surface profiles in the case file


@dataclass(frozen=True)
class Limits:
    """The cost guards (``limits``): refused before computing, or ended as diverged."""

    max_dofs: float
    max_memory_gb: float
    refuse_locking: bool
    max_steps: int


@dataclass(frozen=True)
class Verification:
    """The load sweep of the Hertz and JKR scenes (``verification``)."""

    loads: tuple[float, ...]  # P = -Fn (E L0 W), compressive positive
    checkpoint_every: int = 0  # converged steps between the edge-controlled sweep's saves inside a leg (0: none)


@dataclass(frozen=True)
class SolverSpec:
    linear: str  # auto, amg, lu_krylov or direct (see capslide.solvers.linsolve.choose_linear_solver)
    amg_above_dofs: int
    newton_rtol: float
    newton_atol: float
    newton_max_iterations: int
    krylov_rtol: float
    factorization: str = "superlu"  # LU factors of lu_krylov: superlu or pardiso (capslide.solvers.pardiso)
    factor_precision: str = "double"  # PARDISO's factors in double or single precision
    snap_through: bool = False  # a step failing below the minimum step is tried by pseudo-transient continuation
    longest_step_max_growth: float | None = None  # Newton's fallback step's largest residual growth (None: any)


def spring_unit(config: Mapping) -> float:
    """What loading.spring_stiffness is divided by: E (Pa) for the 2D cap's spring per unit width (N/m per m), E L0
    (N/m) for the 3D sphere's spring (mesh.element = H1 or H2)."""
    E, L0 = config["material"]["E"], config["geometry"]["L0"]
    return E * L0 if config["mesh"]["element"] in SPHERE_ELEMENTS else E


def _check_path_time(L: Loading, velocity_si: float | None) -> None:
    """ConfigError when the stage's speed makes the path's times (s) overflow: every leg's length (L0) over the
    speed (L0/s), and the dwell, must add up to a finite time."""
    if L.velocity is None:
        return
    length = (L.approach_start_gap + L.approach_edge_step + abs(L.ubar_max) * (2.0 if L.slide_back else 1.0)
              + 2.0 * (abs(L.retract_from) + abs(L.preload) + sum(abs(v) for v in L.preload_via)) + 1.0)
    with np.errstate(over="ignore", divide="ignore"):
        total = np.float64(length) / np.float64(L.velocity) + L.dwell
    if not (L.velocity > 0.0 and math.isfinite(total)):
        raise ConfigError(f"loading.velocity = {velocity_si!r} is not allowed: the path of about {length:.3g} L0 would "
                          "take an infinite time at it (give a speed whose times are finite)")


@dataclass(frozen=True)
class Parameters:
    """Everything a computation needs, in internal units, plus the config."""

    units: Units
    material: Material
    adhesion: Adhesion
    friction: Friction
    contact: ContactSpec
    geometry: Geometry
    mesh: MeshSpec
    loading: Loading
    solver: SolverSpec
    output: Output
    limits: Limits
    verification: Verification
    config: Mapping[str, Any] = field(repr=False, compare=False)

    @classmethod
    def from_config(cls, config: Mapping[str, Any]) -> Parameters:
        """Build from a *validated* configuration (see :func:`capslide.config.validate`)."""
        mat, adh, fr = config["material"], config["adhesion"], config["friction"]
        geo, msh, load, sol = config["geometry"], config["mesh"], config["loading"], config["solver"]
        units = Units(E=float(mat["E"]), L0=float(geo["L0"]))
        lam, mu = lame_plane_strain(1.0, float(mat["nu"]))
        try:
            c = cgcm_constants(adh["T_max"] / units.E, adh["W_adh"] / units.energy_per_area)
            bad = next((k for k, v in c.items() if not (math.isfinite(v) and v > 0.0)), None)
        except (ZeroDivisionError, OverflowError):
            c, bad = {"r0": math.nan}, "r0"
        if bad is not None:  # finite inputs whose ratios over- or underflow in internal units
            raise ConfigError(f"adhesion.T_max = {adh['T_max']!r}, adhesion.W_adh = {adh['W_adh']!r}, material.E = "
                              f"{mat['E']!r} and geometry.L0 = {geo['L0']!r} give {bad} = {c[bad]!r} in units of E and "
                              "L0: not computable")
        g_max = c["g_max"]
        if adh["law"] == "dugdale":  # the contact edge: where the repulsion's line reaches the tension T_max
            g_max = c["g_eq"] + adh["dugdale_penalty"] * c["W_adh"] / c["T_max"]
        adhesion = Adhesion(
            r0=c["r0"], A_H=c["A_H"], T0=c["T0"], g_eq=c["g_eq"], g_max=g_max,
            T_max=c["T_max"], W_adh=c["W_adh"], g_reg=adh["g_reg_over_g_eq"] * c["g_eq"], law=adh["law"],
            dugdale_ramp=float(adh["dugdale_ramp"]), dugdale_penalty=float(adh["dugdale_penalty"]),
        )
        s_cut = float(fr["s_cut"])
        friction = Friction(
            model=fr["model"],
            tau_DI=fr["mu_DI"] * c["T_max"],
            g_cut_DI=fr["g_cut_DI_over_g_max"] * c["g_max"],
            k_DI=fr["k_DI_times_r0"] / c["r0"],
            mu_EA=float(fr["mu_EA"]),
            s_cut=s_cut,
            g_cut_EA=s_cut * c["g_max"] + (1.0 - s_cut) * c["g_eq"],
            eps_t=float(fr["eps_t"]),
            DI_area=fr["DI_area"],
            static_over_kinetic=float(fr["static_over_kinetic"]),
            slip_weakening_distance=float(fr["slip_weakening_distance"]),
            active_from=fr["active_from"],
            threshold_at=fr["threshold_at"],
        )
        loading = Loading(
            preload=float(load["preload"]), ubar_max=float(load["ubar_max"]),
            approach_start_gap=load["approach_start_gap_over_r0"] * c["r0"],
            approach_end_gap=load["approach_end_gap_over_g_eq"] * c["g_eq"],
            approach_step=load["approach_step_over_r0"] * c["r0"],
            approach_edge_step=float(load["approach_edge_step"]),
            force_step=float(load["force_step"]), min_force_step=float(load["min_force_step"]),
            retract_from=float(load["retract_from"]),
            slide_step=float(load["slide_step"]), max_slide_step=float(load["max_slide_step"]),
            min_slide_step=float(load["min_slide_step"]), stop_at_onset=bool(load["stop_at_onset"]),
            readhesion_snap=load["readhesion_snap"],
            slide_back=bool(load["slide_back"]), max_cutbacks=int(load["max_cutbacks"]),
            slide_growth_iterations=int(load["slide_growth_iterations"]),
            normal_control=load["normal_control"],
            spring_stiffness=None if load["spring_stiffness"] is None else load["spring_stiffness"] / spring_unit(config),
            velocity=None if load["velocity"] is None else load["velocity"] / units.L0,
            dwell=float(load["dwell"]), preload_via=tuple(float(v) for v in load["preload_via"]),
            preload_area=None if load["preload_area"] is None else float(load["preload_area"]),
            preload_area_rtol=float(load["preload_area_rtol"]),
        )
        _check_path_time(loading, load["velocity"])
        return cls(
            units=units,
            material=Material(E=1.0, nu=float(mat["nu"]), lam=lam, mu=mu,
                              prony_g=tuple(float(b["g"]) for b in mat["prony"]),
                              prony_tau=tuple(float(b["tau"]) for b in mat["prony"])),
            adhesion=adhesion,
            friction=friction,
            contact=ContactSpec(
                far_gap=config["contact"]["far_gap_over_r0"] * c["r0"],
                repulsion_only=bool(config["contact"]["repulsion_only"]),
                area_gap=config["contact"]["area_gap_over_g_max"] * g_max,
                normal_traction_area=config["contact"]["normal_traction_area"],
            ),
            geometry=Geometry(R=float(geo["R"]), H=float(geo["H"])),
            mesh=MeshSpec(
                element=msh["element"], size=float(msh["size"]),
                surface_gauss_points=int(msh["surface_gauss_points"]),
                band_half_width=None if msh["band_half_width"] is None else float(msh["band_half_width"]),
                max_size_over_H=float(msh["max_size_over_H"]), formulation=msh["formulation"],
                max_layer_aspect=None if msh["max_layer_aspect"] is None else float(msh["max_layer_aspect"]),
                symmetry_plane=bool(msh["symmetry_plane"]),
                line_band=None if msh["line_band"] is None else (float(msh["line_band"][0]), float(msh["line_band"][1])),
                line_refinement=float(msh["line_refinement"]),
            ),
            loading=loading,
            solver=SolverSpec(
                linear=sol["linear"], amg_above_dofs=int(sol["amg_above_dofs"]), newton_rtol=float(sol["newton_rtol"]),
                newton_atol=float(sol["newton_atol"]),
                newton_max_iterations=int(sol["newton_max_iterations"]),
                snap_through=bool(sol["snap_through"]), longest_step_max_growth=sol["longest_step_max_growth"],
                krylov_rtol=float(sol["krylov_rtol"]), factorization=sol["factorization"],
                factor_precision=sol["factor_precision"],
            ),
            output=Output(snapshot_ubar=tuple(config["output"]["snapshot_ubar"]),
                          checkpoint_every=int(config["output"]["checkpoint_every"]),
                          surface_profiles=bool(config["output"]["surface_profiles"])),
            limits=Limits(max_dofs=float(config["limits"]["max_dofs"]),
                          max_memory_gb=float(config["limits"]["max_memory_gb"]),
                          refuse_locking=bool(config["limits"]["refuse_locking"]),
                          max_steps=int(config["limits"]["max_steps"])),
            verification=Verification(loads=tuple(config["verification"]["loads"]),
                                      checkpoint_every=int(config["verification"]["checkpoint_every"])),
            config=config,
        )
