"""The book's execution: every notebook run from scratch, two at a time, and results shared between chapters once."""

import importlib.util
import os
import subprocess
import sys
import time
from pathlib import Path

import nbformat
import pytest
import yaml

from semitrack.base.files import exclusive

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def execution():
    spec = importlib.util.spec_from_file_location("semitrack_execution", ROOT / "book" / "_ext" /
                                                  "semitrack_execution.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_book_hands_its_execution_to_the_extension():
    """MyST-NB's own execution off and the extension loaded: else the notebooks would run twice, or never."""
    config = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    assert config["execute"]["execute_notebooks"] == "off"
    assert config["execute"]["allow_errors"] is False
    assert "semitrack_execution" in config["sphinx"]["local_extensions"]


def test_every_notebook_of_the_toc_is_executed(execution):
    notebooks = execution.toc_notebooks(ROOT, ROOT / "_toc.yml")
    toc = (ROOT / "_toc.yml").read_text(encoding="utf-8")
    on_disk = sorted(p.stem for p in (ROOT / "book").glob("*.ipynb"))
    assert sorted(p.stem for p in notebooks) == on_disk
    assert all(f"book/{p.stem}" in toc for p in notebooks)


def test_several_kernels_get_one_blas_thread_each(execution):
    one = execution.kernel_environment(1)
    two = execution.kernel_environment(2)
    assert all(two[name] == "1" for name in execution.THREAD_VARIABLES)
    assert all(one.get(name) == os.environ.get(name) for name in execution.THREAD_VARIABLES)


def _notebook(path: Path, *sources: str) -> Path:
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(s) for s in sources]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, path)
    return path


def test_a_notebook_runs_in_its_own_folder_with_its_outputs_handed_over(execution, tmp_path):
    path = _notebook(tmp_path / "a.ipynb", "import os\nprint(os.getcwd())",
                     "import os\nos.environ['OPENBLAS_NUM_THREADS']")
    text, seconds, error = execution.execute(path, 60, "python3", execution.kernel_environment(2))
    cells = nbformat.reads(text, as_version=4).cells
    assert error is None and seconds > 0
    assert cells[0]["outputs"][0]["text"].strip() == str(tmp_path)
    assert cells[1]["outputs"][0]["data"]["text/plain"] == "'1'"


def test_a_notebook_shows_progress_bars_and_the_books_build_does_not(execution, tmp_path):
    """In a Jupyter kernel (stderr an ipykernel stream) a bar is drawn; in the book's kernels
    (SEMITRACK_PROGRESS=0 from this extension) it is not, so no page shows one."""
    path = _notebook(tmp_path / "bar.ipynb", "from semitrack.base.progress import Progress\n"
                     "with Progress('study', 3) as p:\n    p.update(3, 'done')")
    env = {k: v for k, v in os.environ.items() if k not in ("CI", "SEMITRACK_PROGRESS")}
    text, _, error = execution.execute(path, 60, "python3", env)
    assert error is None
    shown = "".join(o.get("text", "") for o in nbformat.reads(text, as_version=4).cells[0]["outputs"])
    assert "3/3" in shown and "done" in shown
    assert execution.kernel_environment(2)["SEMITRACK_PROGRESS"] == "0"
    text, _, error = execution.execute(path, 60, "python3", execution.kernel_environment(1))
    assert error is None and not nbformat.reads(text, as_version=4).cells[0]["outputs"]


def test_an_output_that_shows_a_raw_repr_is_found_and_a_formatted_one_is_not(execution, tmp_path):
    """The build warns (and CI fails) on a printed numpy scalar, array or dict, not on formatted text,
    a string result, or a table whose text fallback is a repr."""
    path = _notebook(tmp_path / "reprs.ipynb", "import numpy as np\nprint([np.float64(2.5) * 3])",
                     "print(f'{np.float64(2.5):.2f} m, {2:d} wheels; np.interp(x) and $G_{11}$ in words')",
                     "np.arange(3.0)", "print({'M': (6, 6)})", "'a string'",
                     "import pandas as pd\npd.DataFrame({'a': [np.int64(1)]})",
                     "print('P1 (kN)', pd.Series([25.0, 31.0], index=[10, 20]).to_dict())", "print([np.True_])")
    text, _, error = execution.execute(path, 60, "python3", execution.kernel_environment(1))
    assert error is None
    found = execution.raw_reprs(nbformat.reads(text, as_version=4))
    assert [line.split(":")[0] for line in found] == ["cell 1", "cell 3", "cell 4", "cell 7", "cell 8"]
    assert "np.float64(7.5)" in found[0] and "array([0., 1., 2.])" in found[1] and "{10: 25.0" in found[3]


def test_a_failing_cell_is_reported_and_shown_where_it_failed(execution, tmp_path):
    path = _notebook(tmp_path / "bad.ipynb", "x = 1", "raise ValueError('the claim does not hold')", "y = 2")
    text, _, error = execution.execute(path, 60, "python3", execution.kernel_environment(1))
    assert error.startswith("CellExecutionError") and "the claim does not hold" in error
    cells = nbformat.reads(text, as_version=4).cells
    assert cells[1]["outputs"][0]["output_type"] == "error" and not cells[2]["outputs"]


def test_a_cell_over_the_limit_is_reported(execution, tmp_path):
    path = _notebook(tmp_path / "slow.ipynb", "import time\ntime.sleep(30)")
    _, seconds, error = execution.execute(path, 2, "python3", execution.kernel_environment(1))
    assert error is not None and "Timeout" in error and seconds < 25


_CHILD = r"""
import sys, time
from pathlib import Path
from semitrack.base.files import exclusive
target = Path(sys.argv[1])
start = time.time()
with exclusive(target):
    print(time.time() - start)
"""


def test_the_lock_makes_a_second_process_wait(tmp_path):
    """While one process holds a result's lock, another's ``exclusive`` blocks until it is released."""
    target = tmp_path / "fit.json"
    with exclusive(target):
        child = subprocess.Popen([sys.executable, "-c", _CHILD, str(target)], stdout=subprocess.PIPE, text=True)
        time.sleep(1.5)  # the child has imported and is waiting on the lock
    waited = float(child.communicate(timeout=60)[0])
    assert child.returncode == 0
    assert waited > 0.3


_TWICE = r"""
import sys, time
from pathlib import Path
from semitrack.equivalent import cache
from semitrack.equivalent.cache import CachedResponse
folder, log = Path(sys.argv[1]), Path(sys.argv[2])
def compute():
    with open(log, "a") as fh:
        fh.write("computed\n")
    time.sleep(1.0)
    return cache._load(Path(sys.argv[3]), CachedResponse)
result = cache.computed_once("k", folder / "result.json", CachedResponse, compute)
print(type(result).__name__)
"""


def test_two_processes_compute_a_cached_result_once(tmp_path):
    """Two chapters asking for one cached result at once: the second reads the first's file."""
    import numpy as np

    import semitrack as st
    from semitrack.base import records
    from semitrack.equivalent.cache import cached_central_response

    seed = tmp_path / "seed"
    response = cached_central_response(st.slab_track(), np.array([100.0, 200.0]), "transfer", cache_dir=seed)
    source = tmp_path / "source.json"
    source.write_text(records.dumps(response), encoding="utf-8")
    folder, log = tmp_path / "cache", tmp_path / "log"
    folder.mkdir()
    runs = [subprocess.Popen([sys.executable, "-c", _TWICE, str(folder), str(log), str(source)],
                             stdout=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [run.communicate(timeout=120)[0].strip() for run in runs]
    assert [run.returncode for run in runs] == [0, 0]
    assert outs == ["CachedResponse", "CachedResponse"]
    assert log.read_text().count("computed") == 1
