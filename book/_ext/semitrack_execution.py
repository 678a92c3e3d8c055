"""Sphinx extension of the semitrack book: every notebook executed from scratch, two at a time.

MyST-NB's ``force`` mode runs the notebooks one after the other as Sphinx reads them, so a
2-core machine builds the book on one core while its kernel waits on the other. This extension
runs them all when the builder starts, in a pool of :data:`WORKERS` kernels that takes the
next notebook as one finishes (a fresh kernel each, in the notebook's folder, the cell limit of
``_config.yml``), and hands Sphinx the executed notebook in place of the file it reads; MyST-NB,
with execution ``off``, renders those outputs as they are. Nothing is kept between builds.

A cell that raises, or a notebook that passes its cell limit, is a warning with the notebook's
name and the cell's traceback (``nbclient``'s error), and the notebook is rendered as far as it
ran: with ``-W`` (CI) the build fails on it, as MyST-NB's ``force`` mode with ``allow_errors:
false`` does; a reader's build without ``-W`` still gives the rest of the book. So is an output
that shows a reader a raw repr (``np.float64(2.5)``, ``array([...])``, a printed dict):
:func:`raw_reprs`. Each notebook's
wall time is logged as MyST-NB logs it ("Executed notebook in ... seconds"), so the build's log
reads the same.
"""

from __future__ import annotations

import os
import re
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import nbclient
import nbformat
import yaml
from sphinx.util import logging

logger = logging.getLogger(__name__)

#: Notebooks executed at once: one per core, at most two.
WORKERS = max(1, min(2, os.cpu_count() or 1))

#: The kernels' BLAS threads: one each when several run at once. Threaded OpenBLAS spins for work,
#: and two kernels' threads on two cores each slowed the other's chapters 2-4x (measured: the
#: boundary chapter 147 s against 41 s alone), where one thread per kernel costs the package's
#: small batched solves next to nothing.
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def kernel_environment(workers: int) -> dict[str, str]:
    """The environment of each kernel: this process's, with one BLAS thread when ``workers`` > 1,
    and no progress bars (a Jupyter kernel's output would otherwise show them in the rendered page)."""
    env = dict(os.environ, SEMITRACK_PROGRESS="0")
    if workers > 1:
        env.update(dict.fromkeys(THREAD_VARIABLES, "1"))
    return env


#: What a reader should not see in a text output: numpy's scalar and array reprs, a printed dict.
RAW_REPR = re.compile(r"\bnp\.(?:float|u?int|complex)\d*\(|\bnp\.(?:bool|str|bytes)_\(|\bnp\.(?:True|False)_"
                      r"|\b\w*array\(\[|\{\s*(?:'[^']*'|\"[^\"]*\"|-?\d[\w.+-]*|\()\s*[:,]")

#: Outputs that MyST-NB renders from a richer form than their text (a table, a figure).
RICH = ("text/html", "image/png", "image/svg+xml", "image/jpeg", "text/markdown", "text/latex")


def raw_reprs(notebook) -> list[str]:
    """Each text output of ``notebook`` (an nbformat node) that shows a raw repr, as ``cell N: line``.

    Printed text and results shown as text only are read; a table or figure (HTML, an image) is
    rendered from its rich form, so its text/plain fallback is not.
    """
    found = []
    for number, cell in enumerate(notebook.cells, start=1):
        for output in cell.get("outputs", ()):
            data = output.get("data", {})
            text = output.get("text", "") if output.get("output_type") == "stream" else (
                "" if any(kind in data for kind in RICH) else data.get("text/plain", ""))
            found += [f"cell {number}: {line.strip()[:120]}" for line in text.splitlines() if RAW_REPR.search(line)]
    return found


def toc_notebooks(root: Path, toc: Path) -> list[Path]:
    """The notebooks of the table of contents ``toc``, in its order (paths under ``root``)."""
    data = yaml.safe_load(toc.read_text(encoding="utf-8"))
    files: list[str] = []

    def walk(node: dict) -> None:
        for key in ("parts", "chapters", "sections"):
            for item in node.get(key, []) or []:
                if "file" in item:
                    files.append(item["file"])
                walk(item)

    walk(data)
    candidates = [root / f"{name}.ipynb" for name in [data["root"], *files]]
    return [path for path in candidates if path.is_file()]


def execute(path: Path, timeout: int, kernel: str, env: dict[str, str]) -> tuple[str, float, str | None]:
    """``path`` executed in a fresh kernel (environment ``env``) in its own folder.

    Returns
    -------
    text : str
        The executed notebook as JSON: every cell's outputs, up to and with the error of a failing cell.
    seconds : float
        Wall time (s).
    error : str or None
        What failed (the cell and its traceback, or the timeout), None when every cell ran.
    """
    notebook = nbformat.read(path, as_version=4)
    start, error = time.perf_counter(), None
    client = nbclient.NotebookClient(notebook, timeout=timeout, kernel_name=kernel, allow_errors=False,
                                     resources={"metadata": {"path": str(path.parent)}})
    try:
        client.execute(env=env)
    except Exception as failure:  # noqa: BLE001 -- a cell's error, the cell limit, a dead kernel: all reported
        error = f"{type(failure).__name__}: {failure}"
    return nbformat.writes(notebook), time.perf_counter() - start, error


def _execute_all(app) -> None:
    """Run every notebook of the book in the pool; keep the executed ones for :func:`_hand_over`.

    A notebook that fails is reported as a warning with its traceback and handed over as far as it
    ran, its error shown: ``-W`` (CI) fails the build on it, a reader's build without it still
    gives the book.
    """
    app.semitrack_executed = {}
    if app.config.nb_execution_mode != "off":
        return  # MyST-NB executes them itself
    root = Path(app.srcdir)
    notebooks = toc_notebooks(root, root / app.config.external_toc_path)
    timeout = int(app.config.nb_execution_timeout)
    logger.info(f"executing {len(notebooks)} notebooks, {WORKERS} at a time [semitrack]")
    began, env = time.perf_counter(), kernel_environment(WORKERS)
    with ThreadPoolExecutor(WORKERS) as pool:  # the work is in the kernels' processes; threads only wait
        futures = {path: pool.submit(execute, path, timeout, app.config.semitrack_kernel, env) for path in notebooks}
        for path, future in futures.items():
            text, seconds, error = future.result()
            app.semitrack_executed[str(path.resolve())] = text
            if error is None:
                logger.info(f"{path}: Executed notebook in {seconds:.2f} seconds [semitrack]")
            else:
                logger.warning(f"{path.relative_to(root)} failed after {seconds:.1f} s: {error}",
                               type="semitrack", subtype="execution")
            for line in raw_reprs(nbformat.reads(text, as_version=4)):
                logger.warning(f"{path.relative_to(root)}: an output shows a raw repr ({line}): format it for a "
                               "reader", type="semitrack", subtype="output")
    logger.info(f"all notebooks executed in {time.perf_counter() - began:.1f} s [semitrack]")


def _hand_over(app, docname: str, source: list[str]) -> None:
    """Give Sphinx the executed notebook instead of the file it read."""
    executed = getattr(app, "semitrack_executed", {})  # on the app: not pickled with the environment
    path = str(Path(app.env.doc2path(docname)).resolve())
    if path in executed:
        source[0] = executed[path]


def setup(app):
    app.add_config_value("semitrack_kernel", "python3", "env")
    app.connect("builder-inited", _execute_all)
    app.connect("source-read", _hand_over)
    return {"parallel_read_safe": False, "parallel_write_safe": True}
