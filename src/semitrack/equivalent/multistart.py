"""Start points and the multi-start schedule of the fit.

**Multi-start.** Start 0 is the track-based guess suggested by the paper (pad stiffness, rail
mass of one bay, lengths of half a bay, bar masses growing along the chain; or a given system);
the others are random log-normal perturbations of it (a factor ``e`` per standard deviation),
drawn with ``numpy.random.default_rng(seed)``. Every start is screened by a short run (100
evaluations); the best three are continued to convergence (trust-region reflective,
``x_scale="jac"``) and then polished by a ``dogbox`` run, which holds the parameters that trf
only creeps towards the lower bound (the "zero" dampers) at the bound and so certifies
convergence in a few steps. The lowest cost wins.

**Hopeless runs stop early.** A run that would still end above the cost it has to beat even if
its cost went on falling twice as fast as over its last 10 iterations is stopped: a screening
run must beat the third-best screening cost so far (else it is not continued), a continued run
the best polished cost so far (else it does not win). A stopped screening run's entry of
``start_costs`` is its cost when it stopped. Measured on the fits of the book, the README and the
tests (the paper's two tracks with seeds 0 and 1, a soft-pad slab, the floating slab, N = 3-10,
the paper's fit frequencies, unconstrained): every fitted system is the same to the last bit,
and a fit takes 35-55 % less time (the paper's ballasted track: 9.0 -> 3.9 s). What it cannot
rule out is a run that would leave a long plateau late in its budget and then win.

BLAS runs single-threaded during the runs: the matrices are tiny, so threads only cost, and on
a loaded 2-core machine a threaded LAPACK call waits for preempted workers (the SVD inside
``least_squares`` was measured 100-300 times slower). A ``threadpoolctl`` limit holds for the
duration of :func:`run_multistart` only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import OptimizeResult, least_squares

from ..base.progress import LIBRARY_DELAY, Progress
from ..base.threads import serial_blas
from .parametrisation import FitParametrisation
from .residuals import Residuals
from .systems import EquivalentSystem

__all__ = ["MultiStartOutcome", "initial_theta", "start_points", "run_multistart"]

# Multi-start schedule: every start gets a short screening run; the best few are continued.
_SCREEN_NFEV = 100
_N_REFINE = 3
_POLISH_NFEV = 300
# Spread of the random starts around the track-based guess, in log units (a factor e^1 = 2.7).
_START_SPREAD = 1.0
# Distance of the start points from the bounds: strictly inside, as trf requires.
_START_MARGIN = 1e-6
# Iterations over which a run's rate of descent is measured before it may be stopped as hopeless.
_PRUNE_WINDOW = 10
# ... and the factor on that rate: a run is stopped only if it would not reach its target even
# falling twice as fast (a run's descent slows as it converges, but may also leave a plateau).
_OPTIMISM = 2.0


class _Hopeless:
    """Callback of ``least_squares``: stop the run when, at :data:`_OPTIMISM` times the rate its cost
    fell over its last :data:`_PRUNE_WINDOW` iterations, it would still be above ``target`` at
    ``budget`` evaluations."""

    def __init__(self, target: float, budget: int):
        self.target, self.budget, self.history = target, budget, []
        self.stopped = False

    def __call__(self, intermediate_result: OptimizeResult) -> None:
        self.history.append((intermediate_result.nfev, intermediate_result.cost))
        if len(self.history) <= _PRUNE_WINDOW:
            return
        (n0, c0), (n1, c1) = self.history[-1 - _PRUNE_WINDOW], self.history[-1]
        rate = max(c0 - c1, 0.0) / max(n1 - n0, 1)
        if c1 - _OPTIMISM * rate * max(self.budget - n1, 0) > self.target:
            self.stopped = True
            raise StopIteration


def _run(fun, x0, target: float | None, max_nfev: int, kw: dict) -> tuple[OptimizeResult, bool]:
    """``least_squares`` from ``x0``, stopped early when hopeless against ``target`` (None: never)."""
    if target is None:
        return least_squares(fun, x0, max_nfev=max_nfev, **kw), False
    hopeless = _Hopeless(target, max_nfev)
    return least_squares(fun, x0, max_nfev=max_nfev, callback=hopeless, **kw), hopeless.stopped


@dataclass(frozen=True)
class MultiStartOutcome:
    """The winner of :func:`run_multistart`.

    Attributes
    ----------
    best : scipy.optimize.OptimizeResult
        The best polished run; ``nfev``/``njev`` count its screening, continuation and polish.
    best_start : int
        Index of the start it came from.
    start_costs : ndarray
        Cost of every start after screening, in start order.
    """

    best: OptimizeResult
    best_start: int
    start_costs: np.ndarray


def initial_theta(model: FitParametrisation) -> np.ndarray:
    """Start 0: reference values, bar masses growing along the chain from 0.2 to 6 rail bays
    (the far bars stand for more and more of the semi-infinite rail, as in Tables 4 and 7)."""
    th = np.zeros(model.n_theta)
    if model.N > 1:
        th[model.slices["m"]] = np.log(np.geomspace(0.2, 6.0, model.N))
    return th


def start_points(model: FitParametrisation, n_starts: int, seed: int,
                 initial: EquivalentSystem | None = None) -> list[np.ndarray]:
    """``n_starts`` start points: the guess (or ``initial``), then random perturbations of it."""
    rng = np.random.default_rng(int(seed))
    th0 = initial_theta(model) if initial is None else model.theta_of(initial)
    starts = [th0] + [th0 + _START_SPREAD * rng.standard_normal(model.n_theta) for _ in range(n_starts - 1)]
    return [model.inside(s, _START_MARGIN) for s in starts]


def _refine(problem: Residuals, screened: OptimizeResult, max_nfev: int, kw: dict,
            to_beat: float | None = None) -> OptimizeResult | None:
    """Continue a screening run to convergence with trf, then polish it with dogbox; None when
    the continued run was stopped as unable to beat ``to_beat``."""
    model = problem.model
    nfev, njev = screened.nfev, screened.njev or 0
    r = screened
    if screened.status == 0:  # continue the screening run to convergence
        r, stopped = _run(problem.fun, model.inside(screened.x), to_beat, max_nfev, kw)
        if stopped:
            return None
        nfev, njev = nfev + r.nfev, njev + (r.njev or 0)
    # Final dogbox run: it holds the parameters that trf drives slowly towards the lower bound
    # (the "zero" springs and dampers) at the bound, so it certifies convergence within a few
    # evaluations where trf would creep to max_nfev.
    rd = least_squares(problem.fun, model.inside(r.x), max_nfev=min(_POLISH_NFEV, max_nfev),
                       **dict(kw, method="dogbox"))
    if rd.status <= 0 < r.status:  # keep trf's certificate if dogbox ran out
        rd.status, rd.message = r.status, r.message
    rd.nfev, rd.njev = nfev + rd.nfev, njev + (rd.njev or 0)
    return rd


def run_multistart(problem: Residuals, starts: list[np.ndarray], max_nfev: int) -> MultiStartOutcome:
    """Screen every start, continue and polish the best few; the lowest cost wins.

    Parameters
    ----------
    problem : Residuals
        The residuals and their Jacobian.
    starts : list of ndarray
        Start points inside the bounds (:func:`start_points`).
    max_nfev : int
        Largest number of evaluations of each continued run (screening and polish use fewer).
    """
    model = problem.model
    kw = dict(jac=problem.jac, bounds=(model.lower, model.upper), method="trf", x_scale="jac")
    screen_nfev = min(_SCREEN_NFEV, max_nfev)
    n_refine = min(_N_REFINE, len(starts))
    with serial_blas(), Progress("equivalent fit", len(starts) + n_refine, unit="run", delay=LIBRARY_DELAY) as bar:
        screened = []
        for s in starts:  # a run stops early once it cannot reach the best _N_REFINE so far
            to_beat = np.sort([r.cost for r in screened])[_N_REFINE - 1] if len(screened) >= _N_REFINE else None
            screened.append(_run(problem.fun, s, to_beat, screen_nfev, kw)[0])
            bar.advance(note=f"screening start {len(screened)} of {len(starts)}")
        start_costs = np.array([r.cost for r in screened])
        best, best_i = None, -1
        for i in np.argsort(start_costs, kind="stable")[:_N_REFINE]:
            r = _refine(problem, screened[i], max_nfev, kw, None if best is None else best.cost)
            if r is not None and (best is None or r.cost < best.cost):
                best, best_i = r, int(i)
            bar.advance(note="refining the best starts")
    return MultiStartOutcome(best=best, best_start=best_i, start_costs=start_costs)
