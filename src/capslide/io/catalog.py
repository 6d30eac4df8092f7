"""The catalog of a case file's variables over the steps and the surface points, and its scalars: one entry per
variable, read by the case files (:mod:`capslide.io.results`), the collected cube (:mod:`capslide.io.cube`) and
checked against ``docs/data.md`` and the step records by the tests.

An entry gives the name, the dimensions, the kind of unit (``length``, ``area``, ``stress``, ``force``, ``energy``:
scaled by the configuration's E and L0, as a 2D case per unit width and a 3D case as the whole body; ``1`` or
``s``), a short ``long_name`` (an axis label, at most 40 characters), a
``description`` with the details, the :class:`capslide.loadpath.measures.StepRecord` field it is read from (None:
derived when the file is written), whether the collected cube keeps it, and when it is present (``velocity``: with
``loading.velocity``; ``profiles``: with ``output.surface_profiles``; ``3d``: in 3D cases).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Variable", "VARIABLES", "variable", "cube_step_variables", "cube_step_coordinates", "case_scalars",
           "recorded_step_variables"]

STEP, PROFILE, SCALAR = ("step",), ("step", "surface_point"), ()
# what a stored value of each kind of unit is divided by, in 2D (per unit width W) and in 3D
NORMALIZATION = {"length": "L0", "area": "L0", "stress": "E", "force": "E L0 W", "energy": "E L0^2 W"}
NORMALIZATION_3D = {"length": "L0", "area": "L0^2", "stress": "E", "force": "E L0^2", "energy": "E L0^3"}


@dataclass(frozen=True)
class Variable:
    name: str
    dims: tuple[str, ...]
    unit: str  # length, stress, force, energy (scaled), 1 or s
    long_name: str
    description: str = ""
    record: str | None = None  # the StepRecord field it is read from; None: derived when the file is written
    cube: bool = False  # the collected file keeps it
    coordinate: bool = False
    present: str = "always"  # always, velocity (with loading.velocity), profiles (with output.surface_profiles), 3d
    dtype: str = "float64"  # as stored

    @property
    def normalization(self) -> str | None:
        """What the stored values of a 2D case are divided by ("L0", "E", ...), None for counts, flags and times."""
        return NORMALIZATION.get(self.unit)

    def normalization_in(self, dim: int) -> str | None:
        """What the stored values are divided by in a case of dimension ``dim``."""
        return (NORMALIZATION if dim == 2 else NORMALIZATION_3D).get(self.unit)


VARIABLES = (
    # coordinates on step
    Variable("phase", STEP, "1", "load phase", record="phase", cube=True, coordinate=True),
    Variable("ubar", STEP, "length", "tangential displacement ubar", "tangential displacement of the substrate",
             record="ubar", cube=True, coordinate=True),
    Variable("h", STEP, "length", "substrate height h", "height of the substrate's lower face above the base",
             record="h", cube=True, coordinate=True),
    Variable("time", STEP, "s", "time", "time since the start of the approach", record="time", cube=True,
             coordinate=True, present="velocity"),
    # variables on step
    Variable("Fn", STEP, "force", "normal force Fn", "normal contact force on the cap, positive = tensile", "Fn", True),
    Variable("Ft", STEP, "force", "friction force Ft",
             "tangential contact force on the cap, positive in the sliding direction", "Ft", True),
    Variable("area", STEP, "area", "contact area A", "current length (3D: area) where g_n <= {area_gap:.5g} L0", "area",
             True),
    Variable("area_compressive", STEP, "area", "compressive contact area", "current length (3D: area) where Tn >= 0",
             "area_compressive", True),
    Variable("area_stick", STEP, "area", "stick area", "current length of sticking points in contact", "area_stick",
             True),
    Variable("x_left", STEP, "length", "left contact edge x", "current x of the left (trailing) contact edge",
             "x_left", True),
    Variable("x_right", STEP, "length", "right contact edge x", "current x of the right (leading) contact edge",
             "x_right", True),
    Variable("width_y", STEP, "length", "contact width along y",
             "3D: the contact's current width across the sliding direction (the whole body's)", "width_y", True,
             present="3d"),
    Variable("area_reference", STEP, "area", "reference contact area",
             "reference length of the contact (the contact area in the reference configuration)", "area_reference",
             True),
    Variable("x_stick_left", STEP, "length", "left stick edge x",
             "current x of the stick zone's left edge (NaN: nothing sticks)", "x_stick_left", True),
    Variable("x_stick_right", STEP, "length", "right stick edge x",
             "current x of the stick zone's right edge (NaN: nothing sticks)", "x_stick_right", True),
    Variable("elastic_energy", STEP, "energy", "strain energy", "strain energy of the cap per unit width",
             "elastic_energy", True),
    Variable("adhesion_energy", STEP, "energy", "adhesion energy",
             "adhesive potential of the interface per unit width (NaN with theta_k = J_s)", "adhesion_energy", True),
    Variable("penalty_energy", STEP, "energy", "penalty energy",
             "elastic energy of the tangential penalty per unit width", "penalty_energy", True),
    Variable("Ft_over_area", STEP, "stress", "Ft / A", "mean shear stress in contact (NaN without contact)", None,
             True),
    Variable("extent_ratio", STEP, "1", "contact extents' ratio x / y",
             "3D: the contact's extent along x over its width along y, (x_right - x_left) / width_y (1: circular; NaN "
             "without contact)", None, True, present="3d"),
    Variable("dissipation", STEP, "energy", "dissipated work",
             "frictional work dissipated up to the step, per unit width: sum over steps of -(Tt before + Tt after) "
             "/ 2 x slip x dA", None, True),
    Variable("external_work", STEP, "energy", "work of the loads",
             "work of the loads on the substrate up to the step, per unit width: int Fn dh + Ft dubar "
             "(trapezoidal rule)", None, True),
    Variable("energy_residual", STEP, "energy", "energy balance residual",
             "external_work - (elastic + adhesion + penalty energy, change from step 0) - dissipation", None, True),
    Variable("newton_iterations", STEP, "1", "Newton iterations of the step", record="newton_iterations", cube=True,
             dtype="int32"),
    Variable("krylov_iterations", STEP, "1", "Krylov iterations of the step", record="krylov_iterations", cube=True,
             dtype="int32"),
    Variable("wall_time", STEP, "s", "wall time of the step", record="wall_time", cube=True),
    Variable("steady_step", STEP, "1", "steady long step",
             "1: the step went in one to the next snapshot ubar or the leg's end, the sliding being steady (Ft, area "
             "and gaps unchanged to 1e-8 over the steps before and over it); 0: a step of the adaptive step control",
             "steady_step", True, dtype="int8"),
    Variable("snapped", STEP, "1", "snapped-through step",
             "1: the step was passed by pseudo-transient continuation, or stood as a jump of the contact area at the "
             "smallest step (solver.snap_through): a jump of the state, not a quasi-static step; 0: otherwise",
             "snapped", True, dtype="int8"),
    Variable("base_force_x", STEP, "force", "base force x",
             "x force of the clamped base on the cap; force balance: Ft + base_force_x = 0", "reaction", True),
    Variable("base_force_y", STEP, "force", "base force y",
             "y force of the clamped base on the cap; force balance in 2D: Fn + base_force_y = 0", "reaction", True),
    Variable("base_force_z", STEP, "force", "base force z",
             "3D: z force of the clamped base on the sphere (the whole body's); force balance: Fn + base_force_z = 0",
             "reaction", present="3d"),
    # profiles on step x surface_point
    Variable("x_current", PROFILE, "length", "current x of the surface point", record="x_surface", present="profiles"),
    Variable("y_current", PROFILE, "length", "current y of the surface point", record="y_surface", present="profiles"),
    Variable("gap", PROFILE, "length", "normal gap g_n", record="gap", present="profiles"),
    Variable("traction_n", PROFILE, "stress", "normal traction Tn", "per reference area, positive = repulsive",
             "traction_n", present="profiles"),
    Variable("traction_t", PROFILE, "stress", "tangential traction Tt", "on the cap per reference area, positive = +x",
             "traction_t", present="profiles"),
    Variable("traction_t_y", PROFILE, "stress", "tangential traction Tt_y",
             "3D: the y part of the tangential traction on the sphere per reference area, positive = +y "
             "(with output.surface_profiles)", "traction_t_y", present="3d"),
    Variable("slip_state", PROFILE, "1", "friction state of the surface point", record="slip_state",
             present="profiles"),
    Variable("slip", PROFILE, "length", "accumulated slip",
             "slip accumulated up to the step: the sum of |slip| of the steps, in contact (3D: of the slip vector's "
             "length)", "slip", present="profiles"),
    Variable("slip_rate", PROFILE, "1", "slip rate per unit ubar",
             "slip of the step per unit ubar, signed (+x: the cap slips in the sliding direction relative to the "
             "substrate; 3D: its x part; NaN where ubar does not change)", present="profiles"),
    # case scalars
    Variable("peak_Ft", SCALAR, "force", "peak Ft", "largest |Ft| while sliding (signed)", cube=True),
    Variable("onset_ubar", SCALAR, "length", "onset ubar", "ubar at the onset of full sliding (NaN: not reached)",
             cube=True),
    Variable("onset_Ft", SCALAR, "force", "onset Ft", "Ft at the onset of full sliding", cube=True),
    Variable("onset_area", SCALAR, "area", "onset area", "contact area at the onset of full sliding", cube=True),
)
_BY_NAME = {v.name: v for v in VARIABLES}


def variable(name: str) -> Variable:
    """The catalog entry of ``name`` (KeyError for a name the catalog does not hold)."""
    return _BY_NAME[name]


def cube_step_variables() -> tuple[str, ...]:
    """The variables over the steps that the collected cube keeps, in the catalog's order."""
    return tuple(v.name for v in VARIABLES if v.dims == STEP and v.cube and not v.coordinate)


def cube_step_coordinates() -> tuple[str, ...]:
    """The coordinates over the steps that the collected cube keeps."""
    return tuple(v.name for v in VARIABLES if v.dims == STEP and v.cube and v.coordinate)


def case_scalars() -> tuple[str, ...]:
    """The case scalars (onset of full sliding, peak Ft)."""
    return tuple(v.name for v in VARIABLES if v.dims == SCALAR)


def recorded_step_variables() -> tuple[Variable, ...]:
    """The variables over the steps read from one scalar field of the step records, as they are."""
    return tuple(v for v in VARIABLES if v.dims == STEP and not v.coordinate and v.record not in (None, "reaction"))
