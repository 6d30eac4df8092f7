"""Model figures render to non-empty PDF and PNG files (what they show is checked by eye)."""

import pytest

from capslide import figures


@pytest.mark.parametrize("name", list(figures.MODEL_FIGURES))
def test_model_figure_renders(name, paper, tmp_path):
    outputs = [tmp_path / f"{name}.pdf", tmp_path / f"{name}.png"]
    with figures.journal_style():
        figures.save(figures.MODEL_FIGURES[name](paper), outputs)
    for path in outputs:
        assert path.stat().st_size > 5000
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in outputs)  # no temporary left
