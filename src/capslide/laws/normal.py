"""The normal law of a configuration, chosen once: the CGCM traction (the paper's law, :mod:`.contact`) or the
Dugdale verification law (:mod:`.dugdale`). Each gives ``traction(g) -> (Tn, dTn/dg)`` (stress, repulsive
positive) and ``potential(g, g_far) -> phi`` (energy per area, dphi/dg = -Tn, zero from ``g_far`` on, as the
contact integral drops the tail there)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..params import Adhesion
from . import contact
from .dugdale import DugdaleLaw

__all__ = ["CGCMLaw", "NormalLaw", "normal_law"]


@dataclass(frozen=True)
class CGCMLaw:
    """The regularized CGCM traction of constants T0, r0 and regularization gap g_reg."""

    T0: float
    r0: float
    g_reg: float

    def traction(self, g) -> tuple[np.ndarray, np.ndarray]:
        return contact.normal_traction(g, self.T0, self.r0, self.g_reg)

    def potential(self, g, g_far: float = np.inf) -> np.ndarray:
        return contact.normal_potential(g, self.T0, self.r0, self.g_reg, g_far)


NormalLaw = CGCMLaw | DugdaleLaw


def normal_law(a: Adhesion) -> NormalLaw:
    """The normal law of the adhesion constants ``a`` (``a.law``: cgcm or dugdale)."""
    if a.law == "dugdale":
        return DugdaleLaw.from_work(a.T_max, a.W_adh, a.g_eq, a.dugdale_ramp, a.dugdale_penalty)
    if a.law != "cgcm":
        raise ValueError(f"adhesion law {a.law!r}: 'cgcm' or 'dugdale'")
    return CGCMLaw(a.T0, a.r0, a.g_reg)
