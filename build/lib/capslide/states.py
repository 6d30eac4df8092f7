"""Typed states of a computation and their netCDF flag encodings, defined once.

Each state is a small integer (the enum value) with a lower-case name (its label); the CF attributes
``flag_values`` / ``flag_meanings`` of a file variable come from :func:`flag_attributes`.
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

__all__ = ["Phase", "SlipState", "Status", "flag_attributes"]


class _Flag(IntEnum):
    @property
    def label(self) -> str:
        return self.name.lower()

    def __str__(self) -> str:
        return self.label

    @classmethod
    def from_label(cls, text: str):
        """The member named ``text`` (lower case); ValueError naming the allowed labels otherwise."""
        try:
            return cls[str(text).upper()]
        except KeyError:
            allowed = ", ".join(m.label for m in cls)
            raise ValueError(f"{text!r} is not a {cls.__name__} (allowed: {allowed})") from None


class Phase(_Flag):
    """Load phase of a converged step (docs/theory.md section 5); spread: the contact spreads with its edge held (stiff,
    short-range laws, after the approach; the edge-controlled verification sweep); dwell: the hold at the preload
    before the slide (``loading.dwell``)."""

    APPROACH = 0
    PRELOAD = 1
    SLIDE = 2
    SPREAD = 3
    DWELL = 4


class SlipState(_Flag):
    """Friction state of a surface point: out of contact, sticking, slipping, or in contact with no friction acting
    (no friction law, or before friction starts: ``friction.active_from``)."""

    FREE = 0
    STICK = 1
    SLIP = 2
    FRICTIONLESS = 3


class Status(_Flag):
    """How a case ended: completed, the contact came off (detached), no equilibrium was found (diverged), or the
    slide snapped: with slip weakening, no quasi-static equilibrium goes on past a drop of the friction force."""

    COMPLETED = 0
    DETACHED = 1
    DIVERGED = 2
    SNAPPED = 3


def flag_attributes(states: type[_Flag], long_name: str) -> dict:
    """CF attributes of a variable holding members of ``states`` as int8 flags."""
    return {"long_name": long_name, "units": "1", "flag_values": np.array([m.value for m in states], dtype=np.int8),
            "flag_meanings": " ".join(m.label for m in states)}
