"""Paper-style figures; the only layer that imports matplotlib.

One function per figure, each returning a ``matplotlib.figure.Figure``; :func:`save` writes it (PDF, PNG)
atomically. Figure names are the paper's labels (Mergel et al. 2019) without the ``f:`` prefix. The registries
below group the figures by what they are drawn from: a configuration, a mesh file, the collected dataset, one
case file, or the verification tables.
"""

from __future__ import annotations

from collections.abc import Callable

from .cap import fig_cap_Aczoom, fig_cap_FtOverA, fig_cap_PxAndAc, fig_cap_PxOverAc, fig_cap_setup, fig_cap_xn
from .experiment import fig_exp_FnJKR
from .experiment_study import fig_experiment_edges, fig_experiment_panels
from .laws import fig_modelAM, fig_modelCA, fig_Tn, fig_TnTt
from .options import fig_option_edges, fig_options
from .sphere import fig_sphere_Aczoom, fig_sphere_Pa, fig_sphere_Tn
from .studies import fig_convergence, fig_verification
from .style import journal_style, save

__all__ = ["MODEL_FIGURES", "MESH_FIGURES", "CASES_FIGURES", "CASE_FIGURES", "TABLE_FIGURES", "SPHERE_FIGURES",
           "journal_style", "save",
           "fig_convergence", "fig_options", "fig_option_edges", "fig_experiment_panels", "fig_experiment_edges"]

MODEL_FIGURES: dict[str, Callable] = {"Tn": fig_Tn, "modelCA": fig_modelCA, "modelAM": fig_modelAM, "TnTt": fig_TnTt,
                                      "exp_FnJKR": fig_exp_FnJKR}
MESH_FIGURES: dict[str, Callable] = {"cap_setup": fig_cap_setup}
CASES_FIGURES: dict[str, Callable] = {"cap_PxAndAc": fig_cap_PxAndAc, "cap_PxOverAc": fig_cap_PxOverAc,
                                      "cap_FtOverA": fig_cap_FtOverA,  # the same figures of the sphere's study (3D):
                                      "sphere_PxAndAc": fig_cap_PxAndAc, "sphere_PxOverAc": fig_cap_PxOverAc,
                                      "sphere_FtOverA": fig_cap_FtOverA}
CASE_FIGURES: dict[str, Callable] = {"cap_Aczoom": fig_cap_Aczoom, "cap_xn": fig_cap_xn}
TABLE_FIGURES: dict[str, Callable] = {"verification": fig_verification}
SPHERE_FIGURES: dict[str, Callable] = {"sphere_Tn": fig_sphere_Tn, "sphere_Pa": fig_sphere_Pa,  # a 3D case file
                                       "sphere_Aczoom": fig_sphere_Aczoom}
