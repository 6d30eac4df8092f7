"""The tutorial notebook (docs/tutorial.ipynb) runs from top to bottom in a Jupyter kernel (nbclient), and its run
shows the progress widget (tqdm.auto), not a text line per step."""

import nbformat
from nbclient import NotebookClient

from conftest import ROOT


def test_the_tutorial_runs(tmp_path):
    nb = nbformat.read(ROOT / "docs" / "tutorial.ipynb", as_version=4)
    NotebookClient(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [out for cell in nb.cells if cell.cell_type == "code" for out in cell.get("outputs", [])]
    assert not [o for o in outputs if o.output_type == "error"]
    run_cell = next(c for c in nb.cells if "capslide.run(config, progress=True)" in c.source)
    assert any("application/vnd.jupyter.widget-view+json" in o.get("data", {}) for o in run_cell.outputs)
    assert not any("ubar=" in o.get("text", "") for o in run_cell.outputs)  # no log line per step
    assert "completed" in "".join(o.get("text", "") for o in run_cell.outputs)
    assert not list(tmp_path.iterdir())  # the notebook writes in its own temporary folder
