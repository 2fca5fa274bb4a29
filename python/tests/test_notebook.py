"""The example notebook runs headless from start to end (its cells assert what they show)."""

from pathlib import Path

import nbformat
from nbclient import NotebookClient

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_tour_notebook_runs():
    notebook = nbformat.read(EXAMPLES / "tour.ipynb", as_version=4)
    NotebookClient(
        notebook, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(EXAMPLES)}}
    ).execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    shown = [o.get("data", {}) for o in outputs if o.output_type in ("execute_result", "display_data")]
    assert any("text/latex" in d for d in shown), "equations show as LaTeX"
    assert any("image/svg+xml" in d for d in shown), "simulations and diagrams show as SVG"
    assert any("text/markdown" in d for d in shown), "explanations in Markdown render"
