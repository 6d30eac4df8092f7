"""What every file capslide writes must satisfy: CF attributes and units that UDUNITS reads (cf-units)."""

import re

from cf_units import Unit

# the SI unit a normalized quantity converts to, by what it is divided by (the ``normalization`` attribute)
SI = {"divided by L0": "m", "divided by E": "Pa", "divided by E L0 W": "N/m", "divided by E L0^2 W": "J/m"}


def check_cf(ds, name=""):
    """Every variable has a short long_name and, unless it is text, units; every unit parses and converts to its
    physical unit; attribute names are CF-valid; flag variables list a meaning per value."""
    assert ds.attrs["Conventions"].startswith("CF-") and "history" in ds.attrs, name
    for key in ds.attrs:
        assert re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", key), (name, key)
    for var_name, var in ds.variables.items():
        attrs = var.attrs
        assert "long_name" in attrs and len(attrs["long_name"]) <= 40, (name, var_name)  # an axis label
        if var.dtype.kind in "OUS":  # text has no unit
            assert "units" not in attrs, (name, var_name)
            continue
        assert "units" in attrs, (name, var_name)
        unit = Unit(attrs["units"])  # raises when UDUNITS cannot read it
        assert "L0" not in attrs["units"], (name, var_name)
        if "normalization" in attrs:
            assert unit.is_convertible(Unit(SI[attrs["normalization"]])), (name, var_name, attrs["units"])
        elif attrs["units"] not in ("1", "s"):
            raise AssertionError(f"{name}: {var_name} has units {attrs['units']!r} without a normalization")
        if "flag_values" in attrs:
            assert len(attrs["flag_meanings"].split()) == len(attrs["flag_values"]), (name, var_name)
