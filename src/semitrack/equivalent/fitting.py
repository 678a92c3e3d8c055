"""Fitting an equivalent multi-rigid-body system to a track's receptance (paper Sec. 4.4, 5.2).

The paper determines the parameters of the slab layout (Fig. 7) and the ballasted layout
(Fig. 12) by nonlinear least squares (Matlab ``lsqnonlin``): at pre-selected frequencies the
residuals ``Re(alpha_E - alpha)/|alpha|`` and ``Im(alpha_E - alpha)/|alpha|`` of alpha11,
alpha12 and alpha22 are driven to zero, with some parameters tied to the track's characteristic
frequencies by Eq. (19)-(20) (slab) or Eq. (23), (28)-(30) (ballasted). :func:`fit_equivalent`
solves the same problem with :func:`scipy.optimize.least_squares`, in phases, each in the
module that owns its idea:

* argument checks and the default band (the paper's, ``FIT_BANDS``): here;
* **characteristic frequencies**, detected on the target, never hard-coded, and the **fit
  frequencies** and target values: :mod:`.targets`;
* the **parameterisation** ``p = p_ref exp(theta)`` with bounds, and the **constraints**:
  :mod:`.parametrisation`;
* the residuals and their analytic Jacobian, vectorised over frequency (**speed**):
  :mod:`.residuals`, on the matrices of :mod:`.assembly` (the same assembly as the systems);
* the **multi-start** (screening, continuation, polish; BLAS single-threaded):
  :mod:`.multistart`;
* the result, its errors on the dense grid of the band and the warnings: here.

**Identifiability.** In the slab layout the right end of bar j and the left end of bar j+1
move together (they are hinged) and their dampers both go to the ground, so the receptance
determines only the sums ``c_r[j] + c_l[j+1]``: fitted dampers at a joint are not unique,
which is one reason for the zeros in the paper's Table 4 and in our fits. (In the ballasted
layout the two dampers end on different support masses.) Compare fits by their errors, not
by their parameters.

Fits of the paper's tracks take seconds; :func:`~semitrack.equivalent.cache.cached_fit`
computes each one once per process (and once per build with a cache folder).
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..base.checks import MAX_FREQUENCIES, check_band, check_int_at_least, check_work
from ..base.errors import InputError, InputTypeError
from ..base.fields import check_fields
from ..base.paper_values import FIT_BANDS
from ..model.tracks import Track, require_track
from .assembly import LAYOUTS, Layout, check_layout
from .metrics import ELEMENT_ERROR, ELEMENT_ERROR_DEFINITION, ErrorSummary, error_summary
from .multistart import MultiStartOutcome, run_multistart, start_points
from .parametrisation import FitParametrisation, references
from .residuals import Residuals
from .systems import EquivalentSystem, readonly_state
from .targets import (
    CHARACTERISTIC_SEARCH_BAND,
    FitFrequencies,
    Target,
    default_fit_frequencies,
    fit_characteristic_frequencies,
    normalise_target,
    resolve_characteristic,
    select_frequencies,
    target_values,
)

__all__ = [
    "FitResult",
    "fit_equivalent",
    "default_fit_frequencies",
    "fit_characteristic_frequencies",
    "LAYOUTS",
    "POOR_MEDIAN_ERROR",
    "CHARACTERISTIC_SEARCH_BAND",
]

#: A fit whose median error exceeds this is reported as poor (RuntimeWarning): the paper's own
#: Tables 4 and 7 reach about 0.15-0.17 on the dense grid of their bands.
POOR_MEDIAN_ERROR = 0.25
#: Most bars a fit accepts: beyond it the multi-start least squares runs for many minutes (its
#: unknowns and its Jacobian grow with N; N = 12 already takes ~8 s on one core).
MAX_BARS = 20
#: Most starts of the multi-start (each a least-squares run of up to ``max_nfev`` evaluations).
MAX_STARTS = 10_000
#: Most evaluations of one start.
MAX_NFEV = 1_000_000

# The paper's constraint equations of each layout, as :class:`FitResult` names them.
_CONSTRAINT_EQUATIONS = {"slab": "the paper's Eq. (19)-(20) tie k, J to f_n",
                         "ballasted": "the paper's Eq. (23), (28)-(30) tie k, J, s, mu to f_n1, f_n2, f_anti"}


@dataclass(frozen=True, eq=False)
class FitResult:
    """Outcome of :func:`fit_equivalent`.

    Attributes
    ----------
    system : EquivalentSystem
        The fitted :class:`~semitrack.equivalent.systems.SlabEquivalent` or
        :class:`~semitrack.equivalent.systems.BallastedEquivalent` (SI units).
    layout : {"slab", "ballasted"}
        The layout.
    n_bars : int
        Number of bars N.
    constrained : bool
        Whether the paper's constraints tie ``k, J`` (and ``s, mu``) to the characteristic
        frequencies.
    band : (float, float)
        Frequency band of the error measures (Hz).
    median_error, max_error : float
        Median and maximum of the complex relative error ``|alpha_E - alpha| / |alpha|`` of
        alpha11, alpha12 and alpha22 over :attr:`error_frequencies` (-).
    errors : ErrorSummary
        The per-element errors behind them.
    error_frequencies : ndarray
        The dense grid of the error measures (Hz), spacing <= 3 Hz by default.
    characteristic_frequencies : dict
        The characteristic frequencies used by the constraints (Hz): ``f_n`` (slab) or
        ``f_n1, f_n2, f_anti`` (ballasted).
    fit_freqs : ndarray
        The frequencies of the least-squares residuals (Hz).
    success : bool
        True when the best run of ``least_squares`` converged (``status > 0``).
    status : int
        ``least_squares`` status of the best run (0: ``max_nfev`` reached; 1-4: converged).
    message : str
        ``least_squares`` message of the best run.
    cost : float
        Least-squares cost ``0.5 sum r^2`` at the solution, residuals ``r`` being the real and
        imaginary parts of ``(alpha_E - alpha)/|alpha|`` at :attr:`fit_freqs` (-).
    optimality : float
        First-order optimality (inf-norm of the projected gradient) at the solution (-).
    nfev, njev : int
        Function and Jacobian evaluations of the best run (screening, continuation, polish).
    n_starts : int
        Number of starts tried.
    start_costs : ndarray
        Cost of every start after the short screening run (-), in start order (a run stopped
        early because it could not reach the best three: its cost when it stopped).
    best_start : int
        Index of the start that gave the result (0 is the deterministic track-based guess).
    free_parameters : tuple of str
        Names of the fitted parameter families, in the order of :attr:`theta`.
    theta : ndarray
        Solution in the solver's variables, ``log(p / p_ref)`` (-).
    at_bound : ndarray of int
        Per entry of :attr:`theta`: -1 at the lower bound (parameter ~1e-8 of its reference,
        practically zero), +1 at the upper bound, 0 inside (``active_mask`` of least_squares).
    elapsed : float
        Wall-clock time of the fit (s).
    seed : int
        The seed of the multi-start.
    """

    system: EquivalentSystem = field(repr=False)
    layout: Layout
    n_bars: int
    constrained: bool
    band: tuple[float, float]
    median_error: float
    max_error: float
    errors: ErrorSummary = field(repr=False)
    error_frequencies: np.ndarray = field(repr=False)
    characteristic_frequencies: dict[str, float]
    fit_freqs: np.ndarray = field(repr=False)
    success: bool
    status: int
    message: str
    cost: float
    optimality: float
    nfev: int
    njev: int
    n_starts: int
    start_costs: np.ndarray = field(repr=False)
    best_start: int
    free_parameters: tuple[str, ...] = field(repr=False)
    theta: np.ndarray = field(repr=False)
    at_bound: np.ndarray = field(repr=False)
    elapsed: float
    seed: int

    def __post_init__(self):
        check_fields(self)  # a record built by hand is refused here, not in a method

    def __setstate__(self, state: dict) -> None:
        readonly_state(self, state)

    def __repr__(self) -> str:
        """Several lines: the fit's settings, errors (the metric named), solver outcome and system."""
        constraints = _CONSTRAINT_EQUATIONS[self.layout] if self.constrained else "none (all parameters fitted)"
        grid = self.error_frequencies
        char = ", ".join(f"{name} = {value:.2f} Hz" for name, value in self.characteristic_frequencies.items())
        outcome = "converged" if self.success else "NOT converged"
        lines = [
            f"FitResult: {self.layout} layout, N = {self.n_bars} bars",
            f"  constraints     {constraints}",
            f"  band            {self.band[0]:g}-{self.band[1]:g} Hz; errors on {grid.size} frequencies "
            f"(spacing {grid[1] - grid[0]:.3g} Hz)",
            f"  {ELEMENT_ERROR:<15} median {100 * self.median_error:.2f} %, max {100 * self.max_error:.2f} %",
            f"                  ({ELEMENT_ERROR_DEFINITION})",
            f"  cost            {self.cost:.4g} at {self.fit_freqs.size} fit frequencies "
            f"(optimality {self.optimality:.2g})",
            f"  solver          {outcome} (status {self.status}), best of {self.n_starts} starts: "
            f"start {self.best_start}, {self.nfev} evaluations, {self.elapsed:.1f} s, seed {self.seed}",
            f"  characteristic  {char}",
            "",
        ]
        return "\n".join(lines) + repr(self.system)

    __str__ = __repr__

    def diagnostics(self) -> dict:
        """The least-squares diagnostics as a plain dict (for tables and logs)."""
        return {
            "success": self.success, "status": self.status, "message": self.message,
            "cost": self.cost, "optimality": self.optimality, "nfev": self.nfev, "njev": self.njev,
            "n_starts": self.n_starts, "best_start": self.best_start,
            "n_at_lower_bound": int(np.sum(self.at_bound < 0)),
            "n_at_upper_bound": int(np.sum(self.at_bound > 0)), "elapsed_s": self.elapsed,
        }


# --- phase 1: arguments ------------------------------------------------------------------------
@dataclass(frozen=True)
class _Arguments:
    """The checked, normalised arguments of one fit."""

    track: Track
    layout: Layout
    n_bars: int
    band: tuple[float, float]
    seed: int
    constrained: bool
    n_starts: int
    max_nfev: int
    error_df: float
    initial: EquivalentSystem | None
    target: object


def _check_seed(seed) -> int:
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise InputTypeError(f"seed must be a non-negative integer, got {seed!r} ({type(seed).__name__})")
    if seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    return int(seed)


def _check_error_df(error_df) -> float:
    if isinstance(error_df, bool) or not isinstance(error_df, (int, float)) or not (
            math.isfinite(error_df) and error_df > 0):
        raise InputError(f"error_df must be positive and finite (Hz), got {error_df!r}")
    return float(error_df)


def _check_initial(initial, layout: Layout, n_bars: int) -> EquivalentSystem | None:
    if initial is None:
        return None
    if not isinstance(initial, EquivalentSystem):
        raise InputTypeError(f"initial must be an EquivalentSystem, got {type(initial).__name__}")
    if initial.layout != layout or initial.n_bars != n_bars:
        raise InputError(f"initial must be a {layout} system with n_bars = {n_bars}, got a "
                         f"{initial.layout} system with {initial.n_bars} bars")
    return initial


def _check_arguments(track, layout, n_bars, band, seed, constrained, n_starts, target,
                     initial, max_nfev, error_df) -> _Arguments:
    """Check every argument of :func:`fit_equivalent` (the error names it) and fill the defaults."""
    track = require_track(track)
    layout = check_layout(("ballasted" if track.is_ballasted else "slab") if layout is None else layout)
    n_bars = check_int_at_least("n_bars", n_bars, 1)
    check_work(n_bars, MAX_BARS, f"n_bars={n_bars} asks for a fit of {n_bars} bars", "fit fewer bars")
    band = check_band(FIT_BANDS[layout] if band is None else band)
    seed = _check_seed(seed)
    if not isinstance(constrained, (bool, np.bool_)):
        raise InputTypeError(f"constrained must be True or False, got {constrained!r}")
    n_starts, max_nfev = check_int_at_least("n_starts", n_starts, 1), check_int_at_least("max_nfev", max_nfev, 1)
    check_work(n_starts, MAX_STARTS, f"n_starts={n_starts} asks for {n_starts} least-squares runs", "use fewer starts")
    check_work(max_nfev, MAX_NFEV, f"max_nfev={max_nfev} evaluations a start", "allow fewer evaluations")
    error_df = _check_error_df(error_df)
    check_work((band[1] - band[0]) / error_df, MAX_FREQUENCIES, f"error_df={error_df!r} Hz over band={band!r} gives "
               f"{(band[1] - band[0]) / error_df:.3g} error frequencies", "give a larger error_df")
    return _Arguments(
        track=track, layout=layout, n_bars=n_bars, band=band, seed=seed, constrained=bool(constrained),
        n_starts=n_starts, max_nfev=max_nfev,
        error_df=error_df, initial=_check_initial(initial, layout, n_bars),
        target=normalise_target(target),
    )


# --- phase 5: result -----------------------------------------------------------------------------
def _readonly(a) -> np.ndarray:
    a = np.array(a)
    a.setflags(write=False)
    return a


def _system_receptance(system: EquivalentSystem, problem: Residuals, x: np.ndarray) -> np.ndarray:
    """The fitted system's receptance at the error frequencies of ``problem``.

    Where the system's own conditioning check refuses a frequency, the fit's unchecked solve
    gives the values (with a warning), so that the errors are still reported.
    """
    try:
        return system.receptance(problem.f)
    except ValueError as exc:
        warnings.warn(f"fit_equivalent: {exc}; the errors are computed without that check",
                      RuntimeWarning, stacklevel=4)  # the caller of fit_equivalent
    a = problem.alpha(x)
    alpha = np.zeros((problem.f.size, 2, 2), complex)
    alpha[:, 0, 0], alpha[:, 0, 1], alpha[:, 1, 1] = a[:, 0], a[:, 1], a[:, 2]
    alpha[:, 1, 0] = a[:, 1]
    return alpha


def _result(args: _Arguments, model: FitParametrisation, outcome: MultiStartOutcome, char: dict,
            f_fit: np.ndarray, f_err: np.ndarray, alpha_err: np.ndarray, elapsed: float) -> FitResult:
    """Build the :class:`FitResult`: the system of the best run and its errors over the band."""
    best = outcome.best
    system = model.system(best.x)
    summary = error_summary(_system_receptance(system, Residuals(model, f_err, alpha_err), best.x), alpha_err)
    return FitResult(
        system=system, layout=args.layout, n_bars=args.n_bars, constrained=args.constrained, band=args.band,
        median_error=summary.median, max_error=summary.max, errors=summary,
        error_frequencies=_readonly(f_err), characteristic_frequencies=dict(char),
        fit_freqs=_readonly(f_fit), success=bool(best.status > 0), status=int(best.status),
        message=str(best.message), cost=float(best.cost), optimality=float(best.optimality),
        nfev=int(best.nfev), njev=int(best.njev or 0), n_starts=args.n_starts,
        start_costs=_readonly(outcome.start_costs), best_start=outcome.best_start,
        free_parameters=model.names, theta=_readonly(best.x),
        at_bound=_readonly(np.asarray(best.active_mask, int)), elapsed=elapsed, seed=args.seed,
    )


def _warn_if_poor(result: FitResult) -> None:
    """RuntimeWarning when the best run did not converge or its median error is poor."""
    if result.success and result.median_error <= POOR_MEDIAN_ERROR:
        return
    reason = "did not converge" if not result.success else (
        f"is poor (median error {result.median_error:.3g} > {POOR_MEDIAN_ERROR})")
    warnings.warn(
        f"fit_equivalent: the best fit ({result.layout}, N = {result.n_bars}) {reason}: status {result.status} "
        f"({result.message}), cost {result.cost:.4g}, median/max error {result.median_error:.3g}/"
        f"{result.max_error:.3g}, n_starts {result.n_starts}; try more starts (n_starts), a larger "
        "max_nfev, other fit_freqs or another n_bars",
        RuntimeWarning, stacklevel=3,  # the caller of fit_equivalent
    )


# --- the driver -----------------------------------------------------------------------------------
def fit_equivalent(track: Track, layout: Layout | None = None, n_bars: int = 5,
                   band: tuple[float, float] | None = None, fit_freqs: FitFrequencies = None, seed: int = 0,
                   constrained: bool = True, n_starts: int = 20, target: Target = None, *,
                   characteristic: Mapping[str, float] | None = None, initial: EquivalentSystem | None = None,
                   max_nfev: int = 1000, error_df: float = 3.0) -> FitResult:
    """Fit an equivalent multi-rigid-body system to the receptance of a semi-infinite track.

    Solves the paper's least-squares problem (Sec. 4.4, 5.2): residuals
    ``Re(alpha_E - alpha)/|alpha|`` and ``Im(alpha_E - alpha)/|alpha|`` of alpha11, alpha12
    and alpha22 at ``fit_freqs``, minimised with :func:`scipy.optimize.least_squares` (trf,
    analytic Jacobian) from ``n_starts`` deterministic starts. See :mod:`.parametrisation`
    for the parameterisation and the constraints, :mod:`.targets` for the characteristic
    frequencies and :mod:`.multistart` for the multi-start.

    Parameters
    ----------
    track : Track
        The track (paper Table 2 or 5, or any other). It gives the reference values of the
        parameters (pad stiffness, rail mass of one bay, spacing, ...) and, with
        ``target=None``, the receptance to fit.
    layout : {"slab", "ballasted"}, optional
        Layout of the equivalent system (paper Fig. 7 or 12); default ``"ballasted"`` for a
        track with sleepers and ``"slab"`` otherwise.
    n_bars : int
        Number of bars N >= 1 (the paper uses 5), at most :data:`MAX_BARS` (20): the fit's time
        grows fast with N (slab track, one core: N = 5 ~1.5 s, 8 ~2.3 s, 12 ~8 s).
    band : (float, float), optional
        Frequency band (Hz) of the error measures and of the default fit frequencies; default
        the paper's, :data:`~semitrack.base.paper_values.FIT_BANDS` (3-900 Hz slab, 3-750 Hz
        ballasted).
    fit_freqs : None, "paper" or array_like
        Frequencies of the residuals (Hz). None: :func:`default_fit_frequencies` (40
        log-spaced and 40 uniformly spaced over ``band``, plus the characteristic frequencies
        in the band and their +-1, 3, 6 % neighbours: 85 for the slab, 99 for the ballasted
        track on the paper's bands);
        ``"paper"``: the paper's sets (Table 4: 9 frequencies 3-897 Hz; Table 7: 18
        frequencies 3-800 Hz); or any array of positive frequencies.
    seed : int
        Seed of ``numpy.random.default_rng`` for the random starts; the fit is deterministic.
    constrained : bool
        True: ``k, J`` (slab) or ``k, J, s, mu`` (ballasted) follow Eq. (19)-(20) or (23),
        (28)-(30) from the free parameters and the characteristic frequencies (6N - 2 or 8N - 2
        unknowns, as in the paper). False: they are fitted too (8N - 2 or 12N - 2 unknowns).
    n_starts : int
        Number of starts >= 1: start 0 is the track-based guess (or ``initial``), the others
        random perturbations of it. Each is run for 100 evaluations; the best 3 are continued
        to convergence (at most ``max_nfev`` evaluations) and polished. A run that cannot reach
        the best ones at its rate of descent stops early (:mod:`.multistart`).
    target : None, callable or (f, alpha), optional
        The receptance to fit. None: the exact receptance of ``track``
        (:func:`~semitrack.methods.receptance.semi_infinite_receptance`). A callable ``alpha(f)``
        returning shape (n_f, 2, 2) for frequencies in Hz. A pair ``(f, alpha)`` of sampled
        receptances: the fit frequencies must then be among the samples (default: the samples
        in ``band``), and the errors are measured on the samples in ``band``. Units of the
        elements: m/N, 1/N, 1/N, rad/(N m).
    characteristic : dict, optional
        Characteristic frequencies (Hz) to use instead of detecting them with
        :func:`fit_characteristic_frequencies` (on ``target`` when given, else on ``track``):
        ``{"f_n": ...}`` or ``{"f_n1": ..., "f_n2": ..., "f_anti": ...}``.
    initial : EquivalentSystem, optional
        A system of the same layout and ``n_bars`` to use as start 0 instead of the track-based
        guess (its free parameters, clipped to the bounds; with ``constrained=True`` its ``k, J``
        (``s, mu``) are replaced by the constraints). Starting an unconstrained fit from a
        constrained one shows what the constraints cost: the cost can only go down.
    max_nfev : int
        Largest number of function evaluations of each continued run.
    error_df : float
        Largest spacing (Hz) of the dense grid of the error measures.

    Returns
    -------
    FitResult
        The fitted system, its errors over ``band`` and the least-squares diagnostics.

    Raises
    ------
    TypeError, ValueError
        For bad arguments; the message names the argument.

    Warns
    -----
    RuntimeWarning
        When the best run did not converge (``status <= 0``) or the median error exceeds
        :data:`POOR_MEDIAN_ERROR`; the message gives status, message, cost and n_starts.

    See Also
    --------
    semitrack.equivalent.cache.cached_fit : the same fit, computed once.

    Notes
    -----
    BLAS runs single-threaded during the fit (a ``threadpoolctl`` limit).

    Examples
    --------
    Three bars for the slab track up to 300 Hz, two starts (the paper's fits take N = 5, its
    bands and 20 starts, :func:`~semitrack.equivalent.cache.cached_fit` keeps them):

    >>> import semitrack as st
    >>> fit = st.fit_equivalent(st.slab_track(), layout="slab", n_bars=3, band=(3, 300), n_starts=2)
    >>> fit.system.n_bars, fit.success, fit.median_error < 0.1
    (3, True, True)
    """
    t_start = time.perf_counter()
    args = _check_arguments(track, layout, n_bars, band, seed, constrained, n_starts, target, initial,
                            max_nfev, error_df)
    char = resolve_characteristic(args.track, args.layout, args.band, args.target, characteristic)
    f_fit, f_err = select_frequencies(args.layout, args.band, args.target, fit_freqs, char, args.error_df)
    alpha_fit = target_values(args.track, args.target, f_fit, "fit_freqs")
    alpha_err = target_values(args.track, args.target, f_err, "the error frequencies")

    model = FitParametrisation(args.layout, args.n_bars, args.constrained,
                               references(args.track, args.layout, char), char)
    starts = start_points(model, args.n_starts, args.seed, args.initial)
    outcome = run_multistart(Residuals(model, f_fit, alpha_fit), starts, args.max_nfev)
    result = _result(args, model, outcome, char, f_fit, f_err, alpha_err, time.perf_counter() - t_start)
    _warn_if_poor(result)
    return result
