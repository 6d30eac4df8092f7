"""Derived CGCM constants (docs/theory.md section 1) and unit conversion."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from capslide.config import ConfigError, apply_overrides, load_config, validate
from capslide.constants import derived_constants
from capslide.laws.contact import normal_traction_unregularized
from capslide.params import Parameters, cgcm_constants

from conftest import PAPER_CONFIG as PAPER


def test_paper_constants_to_four_digits(paper):
    a = paper.adhesion
    assert a.r0 == pytest.approx(0.13188, rel=5e-5)
    assert a.T0 == pytest.approx(0.33206, rel=5e-5)
    assert a.g_eq == pytest.approx(0.08398, rel=5e-5)
    assert a.g_max == pytest.approx(0.10085, rel=5e-5)
    assert a.T_max == pytest.approx(0.165, rel=1e-12)  # 0.33 MPa / 2 MPa
    assert a.W_adh == pytest.approx(0.0135, rel=1e-12)  # 0.027 J/m^2 / (2 MPa * 1 um)
    _, slope = normal_traction_unregularized(a.g_eq, a.T0, a.r0)
    assert slope == pytest.approx(-30.63, rel=5e-4)


@pytest.mark.parametrize("T_max, W_adh", [(0.165, 0.0135), (1.0, 1.0), (3.7e5, 0.05), (0.02, 0.4)])
def test_constants_reproduce_inputs(T_max, W_adh):
    c = cgcm_constants(T_max, W_adh)
    Tn = lambda g: normal_traction_unregularized(g, c["T0"], c["r0"])[0]  # noqa: E731
    # Tn(g_eq) = 0 and min Tn = -T_max at g_max
    assert abs(Tn(c["g_eq"])) < 1e-12 * c["T0"]
    assert Tn(c["g_max"]) == pytest.approx(-T_max, rel=1e-12)
    g = np.linspace(c["g_eq"], 5 * c["r0"], 200001)
    assert Tn(g).min() >= -T_max * (1 + 1e-12)
    # W_adh = integral of |Tn| from g_eq to infinity (substitute g = g_eq / s, s in (0, 1])
    integrand = lambda s: abs(Tn(c["g_eq"] / s)) * c["g_eq"] / s**2  # noqa: E731
    W, _ = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=1e-13, limit=200)
    assert W == pytest.approx(W_adh, rel=1e-8)
    # closed forms of the paper: W_adh = 15^(1/3) A_H / (16 pi r0^2), T_max = sqrt(5) A_H / (9 pi r0^3)
    assert 15 ** (1 / 3) * c["A_H"] / (16 * math.pi * c["r0"] ** 2) == pytest.approx(W_adh, rel=1e-13)
    assert math.sqrt(5) * c["A_H"] / (9 * math.pi * c["r0"] ** 3) == pytest.approx(T_max, rel=1e-13)


def test_si_to_internal_units_in_one_place(paper_config):
    doubled = apply_overrides(paper_config, ["material.E=4.0e6", "adhesion.T_max=0.66e6", "adhesion.W_adh=0.054"])
    p1, p2 = Parameters.from_config(paper_config), Parameters.from_config(validate(doubled))
    # stresses scale with E, W_adh with E L0: internal values do not change
    assert p2.adhesion.T_max == pytest.approx(p1.adhesion.T_max)
    assert p2.adhesion.r0 == pytest.approx(p1.adhesion.r0)
    si = derived_constants(p1)["SI"]
    assert si["r0"] == pytest.approx(0.13188e-6, rel=5e-5)
    assert si["T_max"] == pytest.approx(0.33e6)
    assert si["W_adh"] == pytest.approx(0.027)


def test_friction_cutoffs(paper_config):
    p = Parameters.from_config(validate(apply_overrides(paper_config, ["friction.s_cut=0.5"])))
    a, f = p.adhesion, p.friction
    assert f.g_cut_EA == pytest.approx(0.5 * (a.g_eq + a.g_max))
    assert f.g_cut_DI == pytest.approx(a.g_max)
    assert f.tau_DI == pytest.approx(a.T_max)
    assert f.k_DI * a.r0 == pytest.approx(50.0)
    assert p.adhesion.g_reg == pytest.approx(a.g_eq)


def test_plane_strain_lame(paper):
    m = paper.material
    assert m.lam == pytest.approx(0.4 / (1.4 * 0.2))
    assert m.mu == pytest.approx(1 / 2.8)


def test_overlay_files_merge(tmp_path):
    from conftest import PAPER_CONFIG

    overlay = tmp_path / "o.yaml"
    overlay.write_text("friction:\n  model: EA\n  s_cut: 0\n")
    cfg = load_config([PAPER_CONFIG, overlay], ["loading.preload=-0.288"])
    assert cfg["friction"]["model"] == "EA" and cfg["friction"]["s_cut"] == 0
    assert cfg["friction"]["mu_DI"] == 1.0  # untouched keys survive the merge
    assert cfg["loading"]["preload"] == -0.288


def test_preset_fills_only_what_nothing_else_sets(tmp_path):
    """The paper's config chooses the 'paper' preset; another preset or an explicit key changes the mesh."""
    paper_config = load_config([PAPER])
    presets = paper_config["presets"]
    assert paper_config["preset"] == "paper" and paper_config["mesh"]["size"] == presets["paper"]["mesh.size"]
    ref = load_config([PAPER], ["preset=reference"])
    assert ref["mesh"]["size"] == presets["reference"]["mesh.size"] < paper_config["mesh"]["size"]
    explicit = load_config([PAPER], ["preset=reference", "mesh.size=3"])
    assert explicit["mesh"]["size"] == 3
    assert validate(explicit) == explicit  # idempotent: a validated config validates to itself
    no_preset = load_config([PAPER], ["preset=null"])
    assert no_preset["mesh"]["size"] == 1.0  # the schema default: the paper's 42,300-element level
    bad = tmp_path / "bad.yaml"
    bad.write_text("presets: {paper: {mesh.sise: 2}}\n")
    with pytest.raises(ConfigError, match="unknown key 'mesh.sise'"):
        load_config([PAPER, bad])


def test_the_constants_si_units_are_derived_and_checked_by_pint(paper):
    """A_H is an energy (J), not 'J m'; each SI value is the internal one times E^a L0^b, converted by pint."""
    import pint

    from capslide.constants import SI_UNITS, _si_quantity

    c = derived_constants(paper)
    assert c["SI_units"]["A_H"] == "J" and c["SI_units"]["W_adh"] == "J/m^2"
    assert c["SI"]["A_H"] == pytest.approx(c["internal"]["A_H"] * 2e6 * 1e-18, rel=1e-12)
    assert c["SI"]["W_adh"] == pytest.approx(0.027, rel=1e-12)
    assert set(SI_UNITS) == set(c["internal"])
    with pytest.raises(pint.DimensionalityError):
        _si_quantity(1.0, paper.units, 1, 3, "J m")  # the old label: an energy times a length
