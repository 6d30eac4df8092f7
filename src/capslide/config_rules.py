"""Cross-key rules of a configuration that its schema cannot express: each raises a one-line ConfigError naming
the key and its value (:func:`capslide.config.validate` applies them after the schema and the defaults)."""

from __future__ import annotations

import math
from collections.abc import Mapping

from .config import SPHERE_ELEMENTS, ConfigError, schema

__all__ = ["LOCKING_NU", "MAX_SPRING_OVER_E", "check_consistency", "derive_from_maugis_lambda", "top_surface"]


# Largest Poisson's ratio at which each displacement element is free of volumetric locking, measured with
# benchmarks/locking.py (docs/stability.md): the zero-load contact area of the paper's cap at the element's preset
# (Q1: fast, Q2: paper) against a converged reference, within the preset's error budget (5 %, 1 %).
# Q1: -3.8 % at nu = 0.45, -6.9 % at 0.48, -10.4 % at 0.49. Q2: -0.11 % at 0.48, -0.16 % at 0.49.
# H1: the sphere scene's zero-load area at its fast preset lies 4.6 % below H1/P0's at nu = 0.4 (docs/three_d.md);
# on Hertz (benchmarks/hertz_sphere.py --R 400, h0 = 0.8) H1's radius departs from H1/P0's by 0.54 % at 0.4 and
# 1.05 % at 0.45. H2: Hertz's peak +0.33 % at 0.49, +24 % at 0.499 (docs/three_d.md).
LOCKING_NU = {"Q1": 0.45, "Q2": 0.49, "H1": 0.4, "H2": 0.49}
MIXED_PAIR = {"Q1": "Q2/P1 with mesh.element = Q2", "Q2": "Q2/P1", "H1": "H1/P0", "H2": "H2/P1"}


def derive_from_maugis_lambda(config: dict) -> None:
    """In place: adhesion.T_max from adhesion.maugis_lambda (the sphere's Maugis parameter at the configuration's
    R, E, nu and W_adh; Maugis 1992, in Johnson and Greenwood's notation), or a ConfigError when T_max is missing,
    set twice, or lambda is given for a 2D cap (whose Maugis parameter is another)."""
    adh, lam = config["adhesion"], config["adhesion"]["maugis_lambda"]
    if lam is None:
        if "T_max" not in adh:
            raise ConfigError("missing key 'adhesion.T_max' (or set it through adhesion.maugis_lambda, 3D only)")
        return
    if config["mesh"]["element"] not in SPHERE_ELEMENTS:
        raise ConfigError(f"adhesion.maugis_lambda = {lam!r} is not allowed with mesh.element = "
                          f"{config['mesh']['element']}: it is the sphere's Maugis parameter (mesh.element = H1 or H2)")
    mat, geo = config["material"], config["geometry"]
    K = 4.0 / 3.0 * mat["E"] / (1.0 - mat["nu"] ** 2)
    # lambda = 2 T_max (R / (pi W K^2))^(1/3), solved for T_max (laws.sphere.dugdale_stress_for_lambda; this layer
    # sits below laws/, and tests/test_verification_3d.py checks the round trip through laws.sphere)
    T_max = float(lam / (2.0 * (geo["R"] * geo["L0"] / (math.pi * adh["W_adh"] * K**2)) ** (1.0 / 3.0)))
    if "T_max" in adh and not math.isclose(adh["T_max"], T_max, rel_tol=1e-12):  # equal: a file's validated config
        raise ConfigError(f"adhesion.T_max = {adh['T_max']!r} is not allowed with adhesion.maugis_lambda = {lam!r}: "
                          "lambda sets T_max (give one of them)")
    adh["T_max"] = T_max


def derive_mu_DI(config: dict) -> None:
    """In place: friction.mu_DI = friction.tau_DI / adhesion.T_max when tau_DI (Pa) is given (after
    :func:`derive_from_maugis_lambda`: the experiment's tau is fixed while lambda sets T_max)."""
    tau = config["friction"]["tau_DI"]
    if tau is not None:
        config["friction"]["mu_DI"] = float(tau / config["adhesion"]["T_max"])


def _check_three_d(config: Mapping) -> None:
    """The 3D sphere's mesh keys (mesh.element = H1, H2) shape only its mesh, and its bulk is elastic in this version
    (the viscous branches are 2D)."""
    line, refinement = config["mesh"]["line_band"], config["mesh"]["line_refinement"]
    if line is None and refinement != schema()["properties"]["mesh"]["properties"]["line_refinement"]["default"]:
        raise ConfigError(f"mesh.line_refinement = {refinement!r} is not allowed with mesh.line_band = None: it refines "
                          "the rings of the contact-line annulus (give mesh.line_band)")
    if config["mesh"]["element"] not in SPHERE_ELEMENTS:
        if config["mesh"]["max_layer_aspect"] is not None:
            raise ConfigError(f"mesh.max_layer_aspect = {config['mesh']['max_layer_aspect']!r} is not allowed with "
                              f"mesh.element = {config['mesh']['element']}: it shapes the 3D sphere's mesh (H1 or H2)")
        if config["mesh"]["line_band"] is not None:
            raise ConfigError(f"mesh.line_band = {config['mesh']['line_band']!r} is not allowed with "
                              f"mesh.element = {config['mesh']['element']}: it shapes the 3D sphere's mesh (H1 or H2)")
        if not config["mesh"]["symmetry_plane"]:
            raise ConfigError(f"mesh.symmetry_plane = False is not allowed with mesh.element = "
                              f"{config['mesh']['element']}: it shapes the 3D sphere's mesh (H1 or H2)")
        return
    if line is not None and not line[0] < line[1]:
        raise ConfigError(f"mesh.line_band = {line!r} is not allowed: its inner radius must be below its outer one")
    if config["material"]["model"] != "neo_hooke":
        raise ConfigError(f"material.model = {config['material']['model']!r} is not allowed with mesh.element = "
                          f"{config['mesh']['element']}: the 3D sphere's bulk is elastic in this version (use 'neo_hooke')")


def _check_locking(config: Mapping) -> None:
    """The displacement formulation locks as nu -> 0.5; the mixed one (Q2/P1) does not, and needs Q2."""
    nu, element, formulation = config["material"]["nu"], config["mesh"]["element"], config["mesh"]["formulation"]
    if formulation == "mixed":
        if element == "Q1":
            raise ConfigError("mesh.formulation = mixed needs mesh.element = Q2 (Q2/P1), H1 (H1/P0) or H2 (H2/P1), not "
                              "Q1")
        return
    if nu == 0.5:
        raise ConfigError("material.nu = 0.5 (incompressible) needs mesh.formulation = mixed with mesh.element = Q2 "
                          "or H1")
    if nu > LOCKING_NU[element] and config["limits"]["refuse_locking"]:
        q2 = f" or mesh.element = Q2 (up to nu = {LOCKING_NU['Q2']})" if element == "Q1" else ""
        advice = (f"use mesh.formulation = mixed ({MIXED_PAIR[element]}, free of locking up to nu = 0.5){q2}"
                  f" or nu <= {LOCKING_NU[element]}")
        measured = "benchmarks/locking.py" if element in ("Q1", "Q2") else "docs/three_d.md"
        raise ConfigError(f"material.nu = {nu!r} is not allowed with mesh.element = {element}: the element locks beyond "
                          f"nu = {LOCKING_NU[element]} ({measured}); {advice} (limits.refuse_locking)")


def _check_viscoelastic(config: Mapping) -> None:
    """The viscous branches need time (a velocity), and branches are given only for the viscoelastic law."""
    mat, velocity = config["material"], config["loading"]["velocity"]
    viscous = mat["model"] == "viscoelastic"
    if viscous and not mat["prony"]:
        raise ConfigError("material.prony = [] is not allowed with material.model = viscoelastic: give a branch {g, tau}")
    if viscous and velocity is None:
        raise ConfigError("loading.velocity = None is not allowed with material.model = viscoelastic: give the stage's "
                          "speed (m/s)")
    if not viscous and mat["prony"]:
        raise ConfigError(f"material.prony = {mat['prony']!r} is not allowed with material.model = {mat['model']}: "
                          "the branches need material.model = viscoelastic")


# Largest spring stiffness / E of loading.normal_control = spring (per unit width: Pa / Pa). Measured on the paper's
# cap at the fast preset (CHANGELOG, Reliability): the slide converges up to k/E = 1e6 and its peak Ft is within
# 1e-6 of height control from k/E = 1e3 on; at k/E = 1e7 Newton stalls at a residual of 4e-9.
MAX_SPRING_OVER_E = 1e5


def _check_no_op_keys(config: Mapping) -> None:
    """Keys that would do nothing in this configuration are refused, not silently ignored."""
    load, fr = config["loading"], config["friction"]
    if load["spring_stiffness"] is not None and load["normal_control"] != "spring":
        raise ConfigError(f"loading.spring_stiffness = {load['spring_stiffness']!r} is not allowed with "
                          f"loading.normal_control = {load['normal_control']}: the spring acts only with normal_control = spring")
    if fr["DI_area"] != "current" and fr["model"] != "DI":
        raise ConfigError(f"friction.DI_area = {fr['DI_area']!r} is not allowed with friction.model = {fr['model']}: "
                          "it sets model DI's threshold")
    if fr["threshold_at"] != "current" and fr["model"] == "none":
        raise ConfigError(f"friction.threshold_at = {fr['threshold_at']!r} is not allowed with friction.model = none: "
                          "there is no threshold")
    sol = config["solver"]
    if sol["factor_precision"] != "double" and sol["factorization"] != "pardiso":
        raise ConfigError(f"solver.factor_precision = {sol['factor_precision']!r} is not allowed with "
                          f"solver.factorization = {sol['factorization']}: it sets the precision of PARDISO's factors")
    adh = config["adhesion"]
    for key, default in (("dugdale_ramp", 0.8), ("dugdale_penalty", 0.005)):
        if adh[key] != default and adh["law"] != "dugdale":
            raise ConfigError(f"adhesion.{key} = {adh[key]!r} is not allowed with adhesion.law = {adh['law']}: it "
                              "shapes the Dugdale law")
    if adh["law"] == "dugdale" and fr["model"] != "none":
        raise ConfigError(f"friction.model = {fr['model']} is not allowed with adhesion.law = dugdale: the Dugdale "
                          "law is a frictionless verification law (model EA's threshold is the CGCM traction's)")
    if load["dwell"] > 0.0 and load["velocity"] is None:
        raise ConfigError(f"loading.dwell = {load['dwell']!r} is not allowed with loading.velocity = None: a dwell is "
                          "time at rest, and a quasi-static path has no time (give the stage's speed, m/s)")


def top_surface(config: Mapping) -> float:
    """The cap's top surface: its arc's length 2 R asin(sqrt(R^2 - (R - H)^2) / R) in 2D (L0), the sphere's cap
    area 2 pi R H in 3D (L0^2)."""
    R, H = config["geometry"]["R"], config["geometry"]["H"]
    if config["mesh"]["element"] in SPHERE_ELEMENTS:
        return 2.0 * math.pi * R * H
    return 2.0 * R * math.asin(math.sqrt(max(R * R - (R - H) ** 2, 0.0)) / R)


def check_consistency(config: Mapping) -> None:
    """Cross-key rules the schema cannot express."""
    _check_locking(config)
    _check_viscoelastic(config)
    _check_three_d(config)
    g_reg_limit = 3.0 ** (1.0 / 6.0)  # g_max / g_eq: beyond it Tn'(g_reg) > 0 and the law never repels
    g_reg = config["adhesion"]["g_reg_over_g_eq"]
    if g_reg >= g_reg_limit:
        raise ConfigError(
            f"adhesion.g_reg_over_g_eq = {g_reg!r} is not allowed: must be < g_max/g_eq = 3^(1/6) = {g_reg_limit:.5f}"
            " (a larger g_reg extrapolates the attractive branch and removes all repulsion)"
        )
    geo = config["geometry"]
    if geo["H"] > geo["R"]:
        raise ConfigError(
            f"geometry.H = {geo['H']!r} is not allowed: must be at most geometry.R = {geo['R']!r} (a cap is at most a half-disc)"
        )
    fr = config["friction"]
    g_cut = fr["g_cut_DI_over_g_max"] * g_reg_limit  # in units of g_eq
    if fr["model"] == "DI" and g_cut <= g_reg:
        raise ConfigError(
            f"friction.g_cut_DI_over_g_max = {fr['g_cut_DI_over_g_max']!r} is not allowed with adhesion.g_reg_over_g_eq = "
            f"{g_reg!r}: the DI cut-off gap must lie above the regularization gap "
            f"(g_cut_DI_over_g_max > {g_reg / g_reg_limit:.5f})"
        )
    # no equilibrium can hold a tensile force above T_max times the whole top surface (a strict bound)
    bound = config["adhesion"]["T_max"] / config["material"]["E"] * top_surface(config)
    preload = config["loading"]["preload"]
    if not config["contact"]["repulsion_only"] and preload > bound:
        raise ConfigError(
            f"loading.preload = {preload!r} is not allowed: beyond pull-off for sure (adhesion cannot carry more than "
            f"T_max/E x top-surface length = {bound:.4g})"
        )
    load = config["loading"]
    if load["normal_control"] == "spring" and load["spring_stiffness"] is None:
        raise ConfigError("loading.spring_stiffness = None is not allowed with loading.normal_control = spring: "
                          "give the spring's stiffness per unit width (Pa; in 3D, mesh.element = H1: N/m)")
    _check_no_op_keys(config)
    k, E = load["spring_stiffness"], config["material"]["E"]
    three_d = config["mesh"]["element"] in SPHERE_ELEMENTS  # the sphere's spring in N/m: against E L0
    scale, unit = (E * config["geometry"]["L0"], "N/m") if three_d else (E, "Pa")
    if load["normal_control"] == "spring" and k / scale > MAX_SPRING_OVER_E:
        raise ConfigError(f"loading.spring_stiffness = {k!r} is not allowed: must be at most {MAX_SPRING_OVER_E:g} x "
                          f"material.E{' x geometry.L0' if three_d else ''} = {MAX_SPRING_OVER_E * scale:g} {unit} "
                          "(stiffer springs are height control to 1e-6 in Ft, and "
                          "their constraint row loses Newton's convergence to round-off): use loading.normal_control = height")
    if config["contact"]["repulsion_only"] and preload > 0.0:
        raise ConfigError(f"loading.preload = {preload!r} is not allowed with contact.repulsion_only: "
                          "a tensile preload needs adhesion")
