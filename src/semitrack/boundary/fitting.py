"""Fitting the broadband boundary: a passive rational end model of a semi-infinite track.

The pipeline of :func:`fit_boundary`, for a track and a band (default 3-3000 Hz):

1. The exact end stiffness ``K = alpha^-1`` (transfer method) on the band's 3 Hz grid plus a
   log-spaced set that resolves the band's low end.
2. The known limits: the static stiffness ``K0 = Re K(f -> 0)`` (evaluated at 1 mHz) and the
   dashpot ``D = diag(sqrt(kappa A G rho A), sqrt(E I rho I))`` of a semi-infinite Timoshenko
   beam end (real moduli) are pinned; vector fitting (:mod:`.vector_fitting`) then fits the
   remainder ``(K - K0)/s - D`` with common poles, weighted by ``|s| / |K_ij|`` (relative
   errors of ``K``).
3. The coefficients are refined on alpha's own relative error (:mod:`.refinement`).
4. Passivity is tested exactly and enforced by perturbing the coefficients with the least growth
   of that error (:mod:`.passivity`).
5. With ``n_poles=None`` the order grows through :data:`ORDERS` until the errors meet ``tol`` or
   stop improving; the best passive model is kept.

The paper's hysteretic (loss-factor) damping is not causal: a stable rational model can match it
only approximately, and the more so the larger the loss factor. Tracks with causal (viscous)
damping are matched to a few tenths of a percent by the same pipeline (their end stiffness is
not rational either, but smooth and causal).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import check_band, check_int_at_least, check_positive, check_positive_pair, check_work
from ..base.deprecation import deprecated_alias
from ..base.errors import InputError
from ..base.fields import check_fields
from ..base.progress import LIBRARY_DELAY, Progress
from ..base.threads import serial_blas
from ..equivalent.mechanical import MatrixSystem
from ..equivalent.metrics import ErrorSummary, error_band_grid, error_summary
from ..methods.receptance import semi_infinite_receptance
from ..model.tracks import Track, require_track
from .passivity import BoundaryPassivityReport, enforce_passivity, passivity_report
from .rational import SYMMETRIC_ELEMENTS, BoundaryStateSpace, RationalEndStiffness
from .refinement import refine_coefficients, relative_alpha_residuals
from .synthesis import second_order_system
from .vector_fitting import starting_poles, vector_fit

__all__ = ["BroadbandBoundary", "fit_boundary", "track_end_limits", "check_n_poles", "ORDERS"]

#: Orders (number of poles, pairs counted twice) tried in turn when ``n_poles`` is None.
ORDERS = (24, 36, 48, 60)
#: Largest order accepted (the cost of a fit grows about quadratically with it).
MAX_POLES = 120
#: Frequency (Hz) at which the static stiffness K0 = Re K(f -> 0) is evaluated.
STATIC_FREQUENCY = 1e-3
#: Largest error grid accepted (band / df), a guard against a mistyped band or step.
MAX_GRID = 100_000
#: Most vector-fitting relocations and starts per order; and their product with the fit's samples,
#: the work of one order (the default fit: ~1 200 samples x 20 relocations x 1 start; measured
#: ~0.5-2 s per order on the paper's tracks, so the limit is a few minutes at most).
MAX_ITERATIONS = 1_000
MAX_STARTS = 100
MAX_FIT_WORK = 1_000_000


def check_n_poles(n_poles: object, name: str = "n_poles") -> int:
    """A number of poles: an integer from 2 to :data:`MAX_POLES`.

    Parameters
    ----------
    n_poles : object
        The value to check.
    name : str
        The parameter name to quote in the message (the CLI says ``--poles``).
    """
    n = check_int_at_least(name, n_poles, 2)
    if n > MAX_POLES:
        raise InputError(f"{name} must be <= {MAX_POLES} (the fit's cost grows with its square), got {n}")
    return n


def track_end_limits(track: Track) -> tuple[np.ndarray, np.ndarray]:
    """The two limits a boundary model pins: static stiffness ``K0`` and the dashpot ``D``.

    Parameters
    ----------
    track : Track
        The track.

    Returns
    -------
    K0 : ndarray, shape (2, 2)
        ``Re K`` at 1 mHz (N/m, N/rad, N m/rad); real symmetric.
    D : ndarray, shape (2, 2)
        ``diag(sqrt(kappa A G rho A), sqrt(E I rho I))`` with the real moduli (N s/m, N m s/rad):
        the impedance of a semi-infinite Timoshenko beam end at high frequency.
    """
    K0 = np.linalg.inv(semi_infinite_receptance(track, [STATIC_FREQUENCY])[0]).real
    D = np.diag([np.sqrt(track.kAG.real * track.rho * track.A), np.sqrt(track.EI.real * track.rho * track.I)])
    return 0.5 * (K0 + K0.T), D


class OrderTrial(NamedTuple):
    """One order fitted by :func:`fit_boundary`'s search (see ``BroadbandBoundary.orders_tried``)."""

    median: float  #: median element error of alpha over the band (-)
    max: float  #: max element error of alpha over the band (-)
    passive: bool  #: passed the Hamiltonian passivity test
    enforcement_rounds: int  #: rounds of passivity enforcement needed
    elapsed: float  #: wall time of this order's fit (s)


#: A recorded damping model of the fitted track ("": not recorded).
TrackDamping = Literal["", "hysteretic", "viscous"]


@dataclass(frozen=True, eq=False)
class BroadbandBoundary:
    """A passive rational model of a semi-infinite track's end, fitted over a band.

    Attributes
    ----------
    rational : RationalEndStiffness
        The rational end stiffness (poles, coefficients, ``K0``, ``D``).
    band : tuple of float
        The fit band (Hz).
    errors : ErrorSummary
        Element-wise relative error of alpha11/alpha12/alpha22 on the band's 3 Hz grid.
    passivity : BoundaryPassivityReport
        The exact passivity test of the final model.
    track_name : str
        Name of the fitted track.
    track_damping : {"", "hysteretic", "viscous"}
        The fitted track's damping model ("" if not recorded, as in files before 0.3): a
        hysteretic track's end is a causal fit to a non-causal target, recorded in every file it
        is written to, and warned about when written for a time-domain code.
    enforcement_rounds : int
        Rounds of passivity enforcement that were needed (0: the refined fit was passive).
    orders_tried : dict
        ``{n_poles: OrderTrial}`` for every order fitted on the way: each order's errors,
        passivity, enforcement rounds and fit time, as ``fit_boundary(..., n_poles=n)`` would
        give them (the same deterministic fit).
    elapsed : float
        Wall time of the fit (s).
    """

    rational: RationalEndStiffness
    band: tuple[float, float]
    errors: ErrorSummary
    passivity: BoundaryPassivityReport
    track_name: str = ""
    track_damping: TrackDamping = ""
    enforcement_rounds: int = 0
    orders_tried: dict = field(default_factory=dict)
    elapsed: float = 0.0

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method

    @property
    def median_error(self) -> float:
        """Median element-wise relative error of alpha over the band (3 Hz grid)."""
        return self.errors.median

    @property
    def max_error(self) -> float:
        """Maximum element-wise relative error of alpha over the band (3 Hz grid)."""
        return self.errors.max

    @property
    def n_poles(self) -> int:
        """Number of poles (pairs counted twice); the model has ``2 n_poles`` states."""
        return self.rational.n_poles

    def dynamic_stiffness(self, f: ArrayLike) -> np.ndarray:
        """End dynamic stiffness ``K(f)``, shape ``(n, 2, 2)``, at any positive frequencies.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz).
        """
        return self.rational.dynamic_stiffness(f)

    def receptance(self, f: ArrayLike) -> np.ndarray:
        """End receptance ``alpha(f) = K(f)^-1``, shape ``(n, 2, 2)``, at any positive frequencies.

        Parameters
        ----------
        f : array_like
            Frequencies (Hz).
        """
        return self.rational.receptance(f)

    def state_space(self) -> BoundaryStateSpace:
        """Real state space with the end velocity as input; unpacks as ``A, B, C, D``."""
        return self.rational.state_space()

    def matrix_system(self) -> MatrixSystem:
        """The end as symmetric positive semi-definite ``M, C, K``: exact, by reciprocal passive synthesis.

        The first two DOFs are the ports, the rail's ``(w, psi)`` at the cut (m, rad; psi the
        clockwise rotation of the cross-section from bending), then at most one internal DOF per
        first-order state (:mod:`~semitrack.boundary.synthesis`). Like every end system it models
        the semi-infinite track to the right of the cut; ``(Q, M)`` is the load applied to the
        ports (the force on the user's end node is ``-(Q, M)``); a left end takes
        ``P = diag(1, -1)`` on the ports. It is accepted wherever an equivalent system is:
        ``TruncatedTrack(track, n, ends="equivalent", system=bnd.matrix_system())``, the time
        domain and :func:`~semitrack.export_system`.

        Limits:

        * **implicit integrators only**: the Maxwell DOFs are massless (Newmark's average
          acceleration, HHT, a BDF; not central differences);
        * **static and preload steps**: the internal DOFs have no spring path to the ground (the
          Maxwell dashpots creep), so ``K`` is singular there; close the cut with the 2x2 ``K0``
          (:meth:`~semitrack.equivalent.mechanical.MechanicalSystem.static_stiffness` equals it),
          then start the dynamic step with the internal DOFs at
          ``system.static_internal(u_static)`` and zero velocity;
        * **mathematical masses**: unit masses in energy coordinates, not physical ones: apply no
          gravity or body load to the internal DOFs (their weight is in the track's preload);
        * **digits**: a file of the matrices needs at least 12 significant digits (measured:
          on the four study fits, 8 digits lose 1e-5 to 4.5 % of the receptance, 12 keep 1e-9 to 1e-5);
          the package's files keep all 17.

        Returns
        -------
        MatrixSystem
            Its ``info`` names the track, band and origin.

        Examples
        --------
        >>> import semitrack as st
        >>> bnd = st.fit_boundary(st.slab_track(damping="viscous"), band=(3, 3000), n_poles=24)
        >>> sys2 = bnd.matrix_system()
        >>> M, C, K = sys2.matrices()
        >>> bool(sys2.is_passive([1.0, 100.0, 1e4])), sys2.n_internal <= 2 * bnd.n_poles
        (True, True)
        """
        return second_order_system(self.rational, info={
            "origin": "broadband boundary (fit_boundary), reciprocal passive synthesis", "track": self.track_name,
            "band_hz": [float(b) for b in self.band], "n_poles": self.n_poles, "track_damping": self.track_damping})

    model = deprecated_alias("rational", "model")
    second_order = deprecated_alias("matrix_system", "second_order")

    def is_passive(self) -> BoundaryPassivityReport:
        """The exact (Hamiltonian) passivity test, re-run on the model; truthy only if passive."""
        return passivity_report(self.rational)

    def __repr__(self) -> str:
        p = "passive (proven)" if self.passivity else "NOT passive"
        return (f"BroadbandBoundary(track={self.track_name!r}, band={self.band} Hz, n_poles={self.n_poles}, "
                f"median_error={self.median_error:.4f}, max_error={self.max_error:.4f}, {p})")


#: Guard samples extend the fit this factor beyond each end of the band (low weight).
GUARD_FACTOR = 30.0


def _check_track_covers(track: Track, band: tuple[float, float]) -> None:
    """Refuse, before any work, a measured track that is not defined where the fit evaluates it."""
    lo, hi = track.frequency_band
    need = (STATIC_FREQUENCY, band[1] * GUARD_FACTOR)
    if lo > need[0] or hi < need[1]:
        raise InputError(f"fit_boundary evaluates the track from {need[0]:g} Hz (its static stiffness K0) to "
                         f"{need[1]:g} Hz (guard samples beyond the band), and this track's measured supports are "
                         f"defined over {lo:g}-{hi:g} Hz only: extend the tables (a row at 0 Hz gives the static "
                         "value) or let them hold their end values (outside = \"hold\")")


def _check_effort(n_starts: object, n_iter: object) -> tuple[int, int]:
    """``n_starts`` and ``n_iter`` checked: integers from 1 to :data:`MAX_STARTS` and :data:`MAX_ITERATIONS`."""
    n_starts = check_int_at_least("n_starts", n_starts, 1)
    n_iter = check_int_at_least("n_iter", n_iter, 1)
    for name, value, limit in (("n_starts", n_starts, MAX_STARTS), ("n_iter", n_iter, MAX_ITERATIONS)):
        check_work(value, limit, f"{name}={value}", f"give {name} <= {limit} (each costs a full fit of the order)")
    return n_starts, n_iter


def _fit_samples(band: tuple[float, float], df: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(fit frequencies, error-grid frequencies, guard mask).

    The fit sees the error grid, a log-spaced set that resolves the band's low end, and guard
    samples a factor :data:`GUARD_FACTOR` beyond each end, without which the model is free to
    turn active (negative damping) just outside the band, where no data holds it.
    """
    grid = error_band_grid(band, df)
    below = np.geomspace(band[0] / GUARD_FACTOR, band[0], 40, endpoint=False)
    above = np.geomspace(band[1], band[1] * GUARD_FACTOR, 41)[1:]
    f = np.unique(np.concatenate([below, grid, np.geomspace(band[0], band[1], 200), above]))
    return f, grid, (f < band[0]) | (f > band[1])


def _one_order(n_poles: int, f: np.ndarray, alpha: np.ndarray, guard: np.ndarray, K0: np.ndarray,
               D: np.ndarray, band: tuple[float, float], rng: np.random.Generator | None, n_iter: int):
    """Vector fit, refinement and passivity enforcement at one order."""
    s = 2j * np.pi * f
    K = np.linalg.inv(alpha)
    G = (K - K0) / s[:, None, None] - D
    data = np.stack([G[:, i, k] for i, k in SYMMETRIC_ELEMENTS], axis=1)
    weights = np.abs(s)[:, None] / np.abs(np.stack([K[:, i, k] for i, k in SYMMETRIC_ELEMENTS], axis=1))
    weights[guard] *= 0.3
    n_pairs = n_poles // 3
    poles = starting_poles(band[0], band[1], n_pairs, n_poles - 2 * n_pairs)
    if rng is not None:  # a multi-start: jitter the starting poles by up to a factor 1.5
        poles = poles * np.exp(rng.uniform(-0.4, 0.4, poles.size))
    poles, coef = vector_fit(s, data, weights, poles, n_iter)
    model, w = refine_coefficients(RationalEndStiffness(poles, coef, K0, D), f, alpha, guard=guard)
    return enforce_passivity(model, linearise=lambda m: relative_alpha_residuals(m, f, alpha, w))


def _search_orders(orders, fit_order, tol) -> dict:
    """Fit the orders in turn; stop at the first that meets ``tol`` or once a larger order
    lowers the maximum error by less than 10 %. Returns ``{order: (model, errors, rounds, s)}``."""
    results = {}
    for order in orders:
        start = time.perf_counter()
        results[order] = (*fit_order(order), time.perf_counter() - start)
        err = results[order][1]
        if err.median <= tol[0] and err.max <= tol[1]:
            break
        maxima = [r[1].max for r in results.values()]
        if len(maxima) > 1 and maxima[-1] > 0.9 * min(maxima[:-1]):
            break
    return results


def _choose(results: dict) -> int:
    """The smallest order whose median and maximum errors are both within 5 % of the best
    passive ones (fewer states make a cheaper time-domain model)."""
    passive = {n: r for n, r in results.items() if passivity_report(r[0])} or results
    best_median = min(r[1].median for r in passive.values())
    best_max = min(r[1].max for r in passive.values())
    good = [n for n, r in passive.items() if r[1].max <= 1.05 * best_max and r[1].median <= 1.05 * best_median]
    return min(good) if good else min(passive, key=lambda n: passive[n][1].max)


#: The band a broadband boundary is fitted over by default (Hz).
DEFAULT_BOUNDARY_BAND = (3.0, 3000.0)


def fit_boundary(track: Track, band: tuple[float, float] = DEFAULT_BOUNDARY_BAND, n_poles: int | None = None,
                 seed: int = 0, *, tol: tuple[float, float] = (0.002, 0.005), df: float = 3.0,
                 n_starts: int = 1, n_iter: int = 20) -> BroadbandBoundary:
    """Fit a passive rational model of the end dynamic stiffness of the semi-infinite ``track``.

    Parameters
    ----------
    track : Track
        The track (hysteretic loss factors as in the paper, or any other).
    band : tuple of float
        Fit band (Hz); the error is judged on its ``df`` grid (at most :data:`MAX_GRID` points).
    n_poles : int, optional
        Number of poles (complex pairs counted twice; ``2 n_poles`` states). ``None`` tries
        :data:`ORDERS` in turn until one meets ``tol`` or a larger order lowers the maximum
        error by less than 10 %, then keeps the smallest order within 5 % of the best median
        and maximum errors (a hysteretic track is limited by causality, not by the order).
    seed : int
        Seed of the starting-pole jitter of the extra starts (``n_starts > 1``); the first start
        is deterministic and uses no random numbers.
    tol : tuple of float
        ``(median, max)`` element-wise relative error of alpha that ends the order search.
    df : float
        Step (Hz) of the error grid.
    n_starts : int
        Starting-pole sets per order (the best is kept).
    n_iter : int
        Vector-fitting pole relocations per start.

    Returns
    -------
    BroadbandBoundary

    Examples
    --------
    >>> import semitrack as st
    >>> bnd = st.fit_boundary(st.slab_track(), band=(3, 3000), n_poles=24)
    >>> bool(bnd.is_passive()), bnd.max_error < 0.1
    (True, True)
    """
    require_track(track)
    band = check_band(band)
    df = check_positive("df", df)
    if (band[1] - band[0]) / df > MAX_GRID:
        raise InputError(f"band / df must give at most {MAX_GRID} frequencies, got band={band} Hz with df={df} Hz")
    check_int_at_least("seed", seed, 0)
    tol = check_positive_pair("tol", tol)
    n_starts, n_iter = _check_effort(n_starts, n_iter)
    orders = ORDERS if n_poles is None else (check_n_poles(n_poles),)
    _check_track_covers(track, band)
    start = time.perf_counter()
    f, grid, guard = _fit_samples(band, df)
    check_work(f.size * n_iter * n_starts, MAX_FIT_WORK,
               f"band={band} Hz with df={df:g} Hz gives {f.size} samples, x n_iter={n_iter} x n_starts={n_starts}",
               "fit a narrower band (a boundary is fitted over 3 Hz - 3 kHz), a larger df, or fewer iterations")
    alpha = semi_infinite_receptance(track, f)
    K0, D = track_end_limits(track)
    on_grid = np.isin(f, grid)

    # at most every order's every start: the search stops at the first order within tol
    bar = Progress("boundary fit", len(orders) * n_starts, unit="start", delay=LIBRARY_DELAY)

    def fit_order(order: int):
        """Best of the starts at one order: (model, errors, enforcement rounds)."""
        results = []
        for k in range(n_starts):
            rng = np.random.default_rng([seed, order, k]) if k else None
            model, rounds = _one_order(order, f, alpha, guard, K0, D, band, rng, n_iter)
            results.append((model, error_summary(model.receptance(grid), alpha[on_grid]), rounds))
            bar.advance(note=f"{order} poles")
        return min(results, key=lambda r: (not passivity_report(r[0]), r[1].max))

    # Many small dense solves: threaded BLAS only adds contention (as in fit_equivalent).
    with serial_blas(), bar:
        results = _search_orders(orders, fit_order, tol)
        bar.finish()  # the search may stop at an early order
    best = _choose(results)
    model, err, rounds, _ = results[best]
    report = passivity_report(model)
    if not report:
        warnings.warn(f"fit_boundary: passivity could not be enforced ({report}); the model may "
                      "generate energy in a time-domain simulation", RuntimeWarning, stacklevel=2)
    return BroadbandBoundary(rational=model, band=band, errors=err, passivity=report, track_name=track.name,
                             track_damping=track.damping, enforcement_rounds=rounds,
                             orders_tried={n: OrderTrial(r[1].median, r[1].max, bool(passivity_report(r[0])),
                                                         r[2], r[3]) for n, r in results.items()},
                             elapsed=time.perf_counter() - start)
