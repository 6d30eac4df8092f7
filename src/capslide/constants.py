"""The constants a configuration derives (CGCM, friction, Lame) in internal units and in SI, for
``capslide constants``: pint converts E^a L0^b into each constant's named SI unit, and refuses a unit of another
dimension."""

from __future__ import annotations

import functools

from .params import Parameters, Units

__all__ = ["SI_UNITS", "derived_constants"]


def derived_constants(params: Parameters) -> dict[str, dict[str, float]]:
    """CGCM and friction constants of ``params``, internal and SI (for ``capslide constants``)."""
    a, f, u = params.adhesion, params.friction, params.units
    internal = {
        "r0": a.r0, "A_H": a.A_H, "T0": a.T0, "g_eq": a.g_eq, "g_max": a.g_max,
        "T_max": a.T_max, "W_adh": a.W_adh, "g_reg": a.g_reg,
        "tau_DI": f.tau_DI, "g_cut_DI": f.g_cut_DI, "k_DI": f.k_DI, "g_cut_EA": f.g_cut_EA,
        "eps_t": f.eps_t, "Lambda": params.material.lam, "mu": params.material.mu,
    }
    dims = {  # powers of (E, L0) of each constant
        "r0": (0, 1), "A_H": (1, 3), "T0": (1, 0), "g_eq": (0, 1), "g_max": (0, 1),
        "T_max": (1, 0), "W_adh": (1, 1), "g_reg": (0, 1), "tau_DI": (1, 0),
        "g_cut_DI": (0, 1), "k_DI": (0, -1), "g_cut_EA": (0, 1), "eps_t": (1, -1),
        "Lambda": (1, 0), "mu": (1, 0),
    }
    si = {k: _si_quantity(v, u, *dims[k], SI_UNITS[k]) for k, v in internal.items()}
    return {
        "internal": internal,
        "internal_units": {k: _internal_unit(*dims[k]) for k in internal},
        "SI": {k: float(q.magnitude) for k, q in si.items()},
        "SI_units": {k: SI_UNITS[k] for k in si},  # each checked by pint's conversion above
    }


# The SI unit each constant is reported in: a name for the reader (J/m^2 for a work of adhesion, where N/m has the
# same dimension); pint converts E^a L0^b into it and raises if the dimension does not match.
SI_UNITS = {"r0": "m", "A_H": "J", "T0": "Pa", "g_eq": "m", "g_max": "m", "T_max": "Pa", "W_adh": "J/m^2",
            "g_reg": "m", "tau_DI": "Pa", "g_cut_DI": "m", "k_DI": "1/m", "g_cut_EA": "m", "eps_t": "Pa/m",
            "Lambda": "Pa", "mu": "Pa"}


@functools.cache
def _registry():
    import pint

    return pint.UnitRegistry()


def _si_quantity(value: float, units: Units, e_pow: int, l_pow: int, unit: str):
    """``value`` in units E^e_pow L0^l_pow as a pint quantity in ``unit`` (DimensionalityError when they differ)."""
    ureg = _registry()
    q = value * (units.E * ureg.pascal) ** e_pow * (units.L0 * ureg.meter) ** l_pow
    return q.to(unit)


def _internal_unit(e_pow: int, l_pow: int) -> str:
    parts = []
    if e_pow:
        parts.append("E")
    if l_pow == 1:
        parts.append("L0")
    elif l_pow > 1:
        parts.append(f"L0^{l_pow}")
    text = " ".join(parts) or "1"
    return f"{text}/L0" if l_pow == -1 else text
