"""The experiment study's evaluation (issue 18): the features it reads from a slide, the findings it states, the
figures, and the spec's expansion and refusals."""

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from capslide.config import ConfigError
from capslide.studies.expansion import runs
from capslide.studies.experiment import features, findings, table_rows

ROOT = Path(__file__).resolve().parents[1]


def slide(drop: float, inward: float, De: float = 1.0) -> dict:
    """A synthetic slide: Ft rises to 1.6 at t = 2 s, then falls by ``drop`` (exponentially); the right edge
    recedes from 5 to 4.8 before the peak, then moves left by ``inward`` after it."""
    t = np.linspace(0.0, 5.0, 501)
    Ft = np.where(t <= 2.0, 0.8 * t, 1.6 - drop * (1.0 - np.exp(-(t - 2.0) / 0.3)))
    x_right = np.where(t <= 2.0, 5.0 - 0.1 * t, 4.8 - inward * (1.0 - np.exp(-(t - 2.0) / 0.5)))
    area = 10.0 - 0.2 * t
    return {"time": t, "ubar": t, "Ft": Ft, "Fn": 0 * t, "area": area, "x_left": x_right - area, "x_right": x_right,
            "Ft_over_area": Ft / area, "status": "completed", "peak_Ft": 1.6, "onset_ubar": 2.1, "De": De}


def test_features_read_the_drop_and_the_edge_from_the_slide():
    f = features(slide(drop=0.08, inward=0.3))
    assert f["t_peak"] == pytest.approx(2.0)
    assert f["drop_pct"] == pytest.approx(100 * 0.08 * (1 - math.exp(-10)) / 1.6, rel=1e-6)
    assert f["drop_time"] == pytest.approx(0.3 * math.log(2), abs=0.011)  # half the fall, on the 0.01 s grid
    assert f["right_edge_inward"] == pytest.approx(0.3 * (1 - math.exp(-6)), rel=1e-6)
    none = features(slide(drop=0.0, inward=0.0))
    assert none["drop_pct"] == 0.0 and math.isnan(none["drop_time"]) and none["right_edge_inward"] == 0.0


def test_findings_state_what_the_numbers_show():
    spec = {"options": {"force_elastic": {"what": "e"}, "force_De1": {"what": "v"}}}
    curves = {("DI", "force_elastic"): slide(0.0, 0.0, math.nan), ("DI", "force_De1"): slide(0.08, 0.3)}
    text = findings(table_rows(spec, curves))
    assert text.startswith("- DI, force control: elastic: no drop of Ft after its peak (0.00 %)")
    assert "De = 1: Ft drops 5.00 % after its peak 1.6000" in text
    assert "the right edge moves inward by 0.299 L0 after the peak" in text


def test_the_figures_draw_every_run(tmp_path):
    from capslide import figures

    spec = yaml.safe_load((ROOT / "config" / "experiment.yaml").read_text())
    curves = {(m, o): slide(0.05, 0.1, math.nan if o.endswith("elastic") else float(o.split("De")[1]))
              for m in spec["models"] for o in spec["options"]}
    with figures.journal_style():
        fig = figures.fig_experiment_panels(spec, curves, "spring")
        assert len(fig.axes) == 8 and all(len(ax.lines) == 8 for ax in fig.axes)  # 4 runs x (line + peak square)
        figures.save(fig, [tmp_path / "panels.png"])
        fig = figures.fig_experiment_edges(spec, curves, "force")
        assert len(fig.axes) == 4 and all(len(ax.lines) == 8 for ax in fig.axes)  # 4 runs x (edge + peak square)
        figures.save(fig, [tmp_path / "edges.png"])
    assert (tmp_path / "panels.png").stat().st_size > 10_000


def test_the_spec_expands_and_every_run_is_viscoelastic_or_the_baseline():
    spec = yaml.safe_load((ROOT / "config" / "experiment.yaml").read_text())
    out = runs(spec, "experiment")
    assert len(out) == 16
    taus = sorted({sets["material.prony"][0]["tau"] for sets in out.values() if "material.prony" in sets})
    assert taus == [0.1, 1.0, 10.0]  # De = tau v / L0 with v = 1 L0/s
    assert all(sets["loading.velocity"] == 1e-6 for sets in out.values())
    with pytest.raises(ConfigError, match="snapshots"):
        runs({**spec, "snapshots": "DI_spring_De1"}, "experiment")
