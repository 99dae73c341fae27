"""The tutorial notebook (examples/python/tutorial.ipynb) runs top to
bottom in a Jupyter kernel, with nbclient, and shows the packing.

Skipped, saying why, when nbclient or ipykernel is missing, unless
``GAPACK_NOTEBOOK_TESTS=required`` (CI), which fails it instead. The
notebook is stored without outputs: a stored output would go stale.
"""

from __future__ import annotations

import json
import os
import time

import pytest

from conftest import ROOT

NOTEBOOK = ROOT / "examples" / "python" / "tutorial.ipynb"
WIDGET = "application/vnd.jupyter.widget-view+json"


def need_notebook_tools():
    """nbformat and nbclient, or a skip (a failure when required)."""
    missing = []
    for module in ("nbformat", "nbclient", "ipykernel", "matplotlib", "pandas"):
        try:
            __import__(module)
        except ImportError:
            missing.append(module)
    if not missing:
        return
    what = f"the notebook test needs {', '.join(missing)} (pip install nbclient ipykernel 'gapack[notebook]')"
    if os.environ.get("GAPACK_NOTEBOOK_TESTS") == "required":
        pytest.fail(f"GAPACK_NOTEBOOK_TESTS=required but {what}")
    pytest.skip(what)


def test_the_notebook_is_stored_without_outputs():
    cells = json.loads(NOTEBOOK.read_text())["cells"]
    code = [c for c in cells if c["cell_type"] == "code"]
    assert code, "the notebook has code"
    assert all(not c["outputs"] and c["execution_count"] is None for c in code)


def test_the_tutorial_runs_and_shows_the_packing(tmp_path):
    need_notebook_tools()
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(NOTEBOOK, as_version=4)
    # The kernel runs in a clean folder: the notebook writes out/ there.
    client = NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    )
    start = time.perf_counter()
    client.execute()  # raises CellExecutionError on the first cell that fails
    print(f"tutorial.ipynb ran in {time.perf_counter() - start:.1f} s")
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    shown = [o for o in outputs if o.output_type in ("display_data", "execute_result")]
    pictures = [o for o in shown if "image/png" in o.get("data", {})]
    assert pictures, "no image/png among the outputs"
    # The packing's own picture: an execute_result with its HTML table too.
    assert any(
        "text/html" in o.data and "data:image/png;base64," in o.data["text/html"] for o in pictures
    ), "the packing did not show itself"
    assert (tmp_path / "out" / "tutorial" / "wells" / "wells.csv").is_file()
    assert (tmp_path / "out" / "tutorial" / "sweep" / "sweep.csv").is_file()
    # The search's progress: tqdm's notebook widget, when tqdm and
    # ipywidgets are installed (as with the notebook extra).
    try:
        import ipywidgets  # noqa: F401
        import tqdm  # noqa: F401
    except ImportError:
        return
    assert any(WIDGET in o.get("data", {}) for o in shown), "no progress widget"
