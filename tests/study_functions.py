"""Functions the study tests run over their cases (a module of their own: dask's workers import it by name)."""

import os
import time
from pathlib import Path

import numpy as np


def eigen(x: int, n: int = 60, pause: float = 0.0) -> dict:
    """A case whose result is sensitive to every bit of BLAS's arithmetic: the largest eigenvalue of a random matrix."""
    time.sleep(pause)  # cases that finish in another order than given
    a = np.random.default_rng(x).standard_normal((n, n))
    w = np.linalg.eigvalsh(a @ a.T)
    return {"largest": float(w[-1]), "trace": float(np.trace(a @ a.T)), "even": x % 2 == 0, "pid": 0 * os.getpid()}


def failing(x: int) -> dict:
    """Raises for odd x, returns a non-dict for x = 4."""
    if x % 2:
        raise ArithmeticError(f"case {x} fails\nsecond line")
    if x == 4:
        return [x]
    return {"x2": 2.0 * x}


def logged(x: int, log: str, pause: float = 0.0) -> dict:
    """Appends the case to ``log`` (one line each) before returning: which cases ran."""
    time.sleep(pause)
    with open(log, "a") as fh:
        fh.write(f"{x}\n")
    return {"y": x + 0.5}


def ran(log: str) -> list[int]:
    """The cases :func:`logged` ran, in the order they ran."""
    path = Path(log)
    return [int(line) for line in path.read_text().split()] if path.exists() else []


def spawns(x: int) -> dict:
    """A case that starts a process of its own (workers must not be daemonic for it)."""
    import multiprocessing

    with multiprocessing.get_context("spawn").Pool(1) as pool:
        return {"y": float(sum(pool.map(abs, [-x, x])))}


def echo(x: float, y: float = 0.0) -> dict:
    """Returns ``y`` as a result when it is not an input of the case."""
    return {"y": 10.0} if y == 0 else {"z": x + y}


def with_a_bar(x: float) -> dict:
    """A case whose work draws a progress bar of its own (the study silences it)."""
    from semitrack.base.progress import Progress

    with Progress("inner work", 2) as bar:
        bar.update(2)
    return {"y": 2 * x}
