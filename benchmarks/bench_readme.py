"""The README's commands timed as a reader runs them, with and without OPENBLAS_NUM_THREADS=1.

Run: python benchmarks/bench_readme.py [--threads default one both] [--skip-book] [--skip-tests] [--busy [N]]

For each thread mode (``default``: the BLAS thread variables unset, as the README's commands run;
``one``: set to 1, as .ci/run sets them), in a child process with that environment:

- the book command, ``jupyter-book build . --all``, from clean, in a temporary copy of this
  working tree (so that the copy's ``_build`` starts empty and this tree's is left alone);
- the test command, ``python -m pytest``, in the same copy;
- one ``fit_equivalent`` of the slab track (N = 5, the paper's band, seed 0), best of three;
- a 500-frequency exact sweep of alpha (the paper's grid), best of twenty;
- the paper's 500-frequency wavenumber sweep of the slab track (its Eq. 14), once.

With ``--busy N`` (``--busy``: two) N CPU-bound processes run all the while (a busy 2-core
machine: a reader's browser, another build); a command that fails, the book beside them
included, stops the script with its output. Prints the wall times side by side, and each
chapter's execution time as the book's log gives it. Nothing is asserted: the numbers go into
the notes. Cell by cell times of the notebooks are :mod:`bench_book`'s job. Takes about twice
(book + tests).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_book import thread_environment  # this folder is on sys.path when run as a script

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
#: What a clean checkout does not have: build output, caches, virtual environments.
NOT_COPIED = shutil.ignore_patterns("_build", ".git", ".venv", "venv", "__pycache__", ".pytest_cache",
                                    "*.egg-info", ".ruff_cache")

# Runs in the child: the two package timings, printed as "fit <s>" and "sweep <s>".
_CHILD = r"""
import time
import semitrack as st
from semitrack.base.paper_values import PAPER_GRID

def best(func, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)

slab = st.slab_track()
print("fit", best(lambda: st.fit_equivalent(slab, layout="slab", n_bars=5, band=(3.0, 900.0), seed=0), 3))
print("sweep", best(lambda: st.semi_infinite_receptance(slab, PAPER_GRID), 20))
print("wavenumber", best(lambda: st.semi_infinite_receptance(slab, PAPER_GRID, method="wavenumber"), 1))
"""
#: A busy job of ``--busy``: one core's worth of pure Python.
_BUSY = "while True: sum(i * i for i in range(10000))"


def environment(mode: str) -> dict[str, str]:
    """:func:`bench_book.thread_environment`, with this Python's folder first on PATH (as after
    ``source .venv/bin/activate``)."""
    env = thread_environment(mode)
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    return env


def timed(args: list[str], cwd: Path, env: dict[str, str]) -> tuple[float, str]:
    """Wall time (s) of one command, and its output; raises if it fails."""
    start = time.perf_counter()
    done = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if done.returncode:
        raise SystemExit(f"{' '.join(args)} failed ({done.returncode}):\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    return wall, done.stdout


def chapter_times(log: str) -> dict[str, float]:
    """Each notebook's execution time (s) from the book's log ("<path>: Executed notebook in <s> seconds")."""
    found = re.findall(r"([\w./-]+)\.ipynb: Executed notebook in ([\d.]+) seconds", log)
    return {Path(path).name: float(seconds) for path, seconds in found}


def measure(mode: str, skip_book: bool, skip_tests: bool) -> dict[str, float]:
    """The four figures of one thread mode (s)."""
    env = environment(mode)
    out = {}
    with tempfile.TemporaryDirectory(prefix="semitrack-bench-") as tmp:
        copy = Path(tmp) / "semitrack"
        shutil.copytree(ROOT, copy, ignore=NOT_COPIED)
        # the copy's package, not this tree's editable install (pytest's doctests of src/ insist)
        env = {**env, "PYTHONPATH": str(copy / "src")}
        if not skip_book:
            out["book"], log = timed([str(BIN / "jupyter-book"), "build", ".", "--all"], copy, env)
            chapters = sorted(chapter_times(log).items(), key=lambda item: -item[1])
            print(f"{mode}: chapters " + ", ".join(f"{name} {seconds:.0f} s" for name, seconds in chapters), flush=True)
        if not skip_tests:
            out["tests"], _ = timed([sys.executable, "-m", "pytest", "-q"], copy, env)
    _, printed = timed([sys.executable, "-c", _CHILD], ROOT, env)
    out.update((name, float(value)) for name, value in (line.split() for line in printed.splitlines()))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--threads", choices=("default", "one", "both"), default="both")
    parser.add_argument("--skip-book", action="store_true")
    parser.add_argument("--skip-tests", action="store_true")
    parser.add_argument("--busy", type=int, nargs="?", const=2, default=0, metavar="N",
                        help="run N CPU-bound processes all the while (two when N is left out)")
    args = parser.parse_args()
    modes = ("default", "one") if args.threads == "both" else (args.threads,)
    busy = [subprocess.Popen([sys.executable, "-c", _BUSY]) for _ in range(max(0, args.busy))]
    print(f"{os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f} at the start"
          + (f"; {len(busy)} CPU-bound job(s) run beside" if busy else ""), flush=True)
    try:
        results = {mode: measure(mode, args.skip_book, args.skip_tests) for mode in modes}
    finally:
        for job in busy:
            job.kill()
    labels = {"book": "jupyter-book build . --all (s)", "tests": "python -m pytest (s)",
              "fit": "fit_equivalent, slab, N = 5 (s)", "sweep": "500-frequency exact sweep (s)",
              "wavenumber": "500-frequency wavenumber sweep (s)"}
    print(f"{'':<34}" + "".join(f"{mode:>12}" for mode in modes))
    for key, label in labels.items():
        if key in results[modes[0]]:
            print(f"{label:<34}" + "".join(f"{results[m][key]:12.3f}" for m in modes))
    print(f"load average {os.getloadavg()[0]:.2f} at the end")
    print("(default: BLAS thread variables unset, as the README's commands run; one: set to 1, as .ci/run)")


if __name__ == "__main__":
    main()
