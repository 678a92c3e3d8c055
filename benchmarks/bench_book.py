"""Time the book's notebooks cell by cell, with and without OPENBLAS_NUM_THREADS=1.

Run: python benchmarks/bench_book.py [--notebooks slab fe ...] [--threads default one both]

Each notebook of _toc.yml runs in a fresh kernel (nbclient, as the book build does), in a child
process whose environment either leaves the BLAS thread variables unset (``default``: what a
reader who types the README's commands gets) or sets them to 1 (``one``: what .ci/run sets).
Prints, per notebook, the wall time and the slowest cell, then the totals. Nothing is asserted:
the numbers go into the notes. The executed notebooks are discarded (no outputs are written).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")

# Runs in the child: executes one notebook and prints {"cells": [seconds, ...]} as JSON.
_CHILD = r"""
import json, sys, time
import nbclient, nbformat
path, workdir = sys.argv[1], sys.argv[2]
nb = nbformat.read(path, 4)
client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                 resources={"metadata": {"path": workdir}})
times = []
with client.setup_kernel():
    for index, cell in enumerate(nb.cells):
        start = time.perf_counter()
        client.execute_cell(cell, index)
        times.append(time.perf_counter() - start if cell.cell_type == "code" else 0.0)
print(json.dumps({"cells": times}))
"""


def toc_notebooks() -> list[str]:
    """The notebooks of _toc.yml, in book order (names without folder and suffix)."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    files = [chapter["file"] for part in toc["parts"] for chapter in part["chapters"]]
    return [Path(f).name for f in files if (ROOT / f"{f}.ipynb").is_file()]


def thread_environment(threads: str) -> dict[str, str]:
    """This process's environment with the BLAS thread variables unset (``default``) or 1 (``one``)."""
    env = {k: v for k, v in os.environ.items() if k not in THREAD_VARIABLES}
    if threads == "one":
        env.update(dict.fromkeys(THREAD_VARIABLES, "1"))
    return env


def run_notebook(name: str, threads: str) -> tuple[float, list[float]]:
    """Wall time (s) of one notebook in a fresh kernel, and the time of each of its cells (s)."""
    env = thread_environment(threads)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", _CHILD, str(ROOT / "book" / f"{name}.ipynb"), str(ROOT / "book")],
                          env=env, capture_output=True, text=True, check=True)
    wall = time.perf_counter() - start
    return wall, json.loads(done.stdout.strip().splitlines()[-1])["cells"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--notebooks", nargs="*", default=toc_notebooks())
    parser.add_argument("--threads", choices=("default", "one", "both"), default="both")
    parser.add_argument("--cells-over", type=float, default=None, metavar="SECONDS",
                        help="also list every cell slower than this (first mode)")
    args = parser.parse_args()
    modes = ("default", "one") if args.threads == "both" else (args.threads,)
    print(f"{os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f} at the start")
    print(f"{'notebook':<12}" + "".join(f"{m + ' (s)':>14}{'slowest cell':>22}" for m in modes))
    totals = dict.fromkeys(modes, 0.0)
    for name in args.notebooks:
        row = f"{name:<12}"
        for mode in modes:
            wall, cells = run_notebook(name, mode)
            totals[mode] += wall
            slow = max(range(len(cells)), key=cells.__getitem__)
            row += f"{wall:14.1f}{f'cell {slow}: {cells[slow]:.1f} s':>22}"
            if mode == modes[0] and args.cells_over is not None:
                slow_cells = [f"{i}: {t:.1f}" for i, t in enumerate(cells) if t > args.cells_over]
        print(row, flush=True)
        if args.cells_over is not None and slow_cells:
            print(f"{'':<12}cells over {args.cells_over:g} s: " + ", ".join(slow_cells), flush=True)
    print(f"{'total':<12}" + "".join(f"{totals[m]:14.1f}{'':>22}" for m in modes))
    print("(default: BLAS thread variables unset, as the README's commands run; one: set to 1, as .ci/run)")


if __name__ == "__main__":
    main()
