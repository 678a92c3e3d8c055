"""Random tracks: every support's properties drawn about the track's, hanging sleepers and failed fasteners.

No built track is periodic: pads, ballast and sleepers scatter, a few sleepers hang over a gap and a
few fasteners have failed. :func:`random_track` draws one such track, a realisation, as local
changes of a nominal :class:`~semitrack.Track` over the supports ``first`` to ``last`` inclusive,
in the ``changes=`` format that :class:`semitrack.InfiniteTrack`, :class:`semitrack.TruncatedTrack`
and :class:`semitrack.WindowTrack` take, and the ``ballast_gaps=`` of the time-domain runs.

The distributions
-----------------
* A support field ``p`` (``kv``, ``kphi``, ``sleeper_mass``, ``kb``) with coefficient of variation
  ``c`` is log-normal with mean (not median) the track's value ``p0``:
  ``p = p0 exp(s z - s^2/2)``, ``s^2 = ln(1 + c^2)``, ``z`` standard normal. Positive, as a
  stiffness or a mass must be.
* ``z`` is independent from support to support, or, with a correlation length ``l`` (m), a
  stationary Gauss-Markov sequence (AR(1)): ``corr(z_i, z_j) = exp(-|x_i - x_j| / l)`` for supports
  ``d`` apart (``d`` the spacing). The correlation length is that of the log of the field, the
  Gaussian behind it; the field's own correlation is ``(exp(s^2 rho) - 1) / (exp(s^2) - 1)``, close to
  ``rho`` for small ``c``. The fields are independent of one another.
* ``voids``: ``round(fraction * n)`` sleepers of the ``n`` supports, drawn without replacement,
  hang over a gap drawn uniform in ``gap = (low, high)`` (m) (or equal to ``gap``). Such a support
  is ``{"kb": 0.0}`` in ``changes`` and ``{k: g}`` in ``ballast_gaps``, as the gap rule of the FE
  models asks (:mod:`semitrack.fe.gaps`): its sleeper rests on the track's ``kb`` once the gap is
  closed. Its other drawn fields (pad, sleeper) stay.
* ``failed``: ``round(failed * n)`` fasteners of the supports not voided have failed: ``{k: None}``,
  no support at all (the pad carries nothing, so neither does what is under it).

Reproducible by construction: each field, the voids and the failed fasteners draw from their own
stream of one :class:`numpy.random.SeedSequence` of ``seed``, so a realisation depends on its seed
only, never on the other realisations of a study, and adding scatter to one field leaves the draws
of the others as they were. ``seed`` may be a tuple, e.g. ``(study_seed, i)`` for realisation ``i``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..base.checks import brief, check_gap, check_in_range, check_int_at_least, check_real
from ..base.errors import InputError, InputTypeError
from ..base.fields import check_fields
from .tracks import Track

__all__ = ["RANDOM_FIELDS", "RandomTrack", "random_track", "lognormal_factors", "autoregression",
           "MAX_RANDOM_SUPPORTS"]

#: The support fields that may scatter: those every model's ``changes`` takes (the FE models' fields).
RANDOM_FIELDS = ("kv", "kphi", "sleeper_mass", "kb")
#: Fields a track without sleepers does not have.
_BALLAST_FIELDS = ("sleeper_mass", "kb")
#: Most supports of one realisation: 10^6 supports is 600 km of track, beyond any model's reach.
MAX_RANDOM_SUPPORTS = 1_000_000
#: Largest coefficient of variation (a factor whose standard deviation is ten times its mean).
MAX_COV = 10.0
#: Largest correlation length (m): beyond it the field is one value over any model.
MAX_CORRELATION_LENGTH = 1e6
#: Largest gap under a hanging sleeper (m): a gap beyond 50 mm is a length typed in mm; a sleeper that
#: never reaches the ballast is ``changes={k: {"kb": 0.0}}`` without a gap.
MAX_GAP = 0.05
#: The stream of each draw in the seed's :class:`numpy.random.SeedSequence` (fixed: a new field takes a new one).
_STREAMS = {"kv": 0, "kphi": 1, "sleeper_mass": 2, "kb": 3, "voids": 4, "failed": 5}
#: Largest seed entry (plus one): 64 bits, as the package's records hold integers.
_MAX_SEED = 2**64


def lognormal_factors(rng: np.random.Generator, cov: float, n: int, correlation: float = 0.0) -> np.ndarray:
    """``n`` log-normal factors of mean 1 and coefficient of variation ``cov``.

    Parameters
    ----------
    rng : numpy.random.Generator
        The stream.
    cov : float
        Coefficient of variation (-), >= 0.
    n : int
        How many.
    correlation : float
        Correlation of the logs of neighbours, ``exp(-d / l)`` (0: independent; < 1).

    Returns
    -------
    ndarray, shape (n,)
    """
    sigma2 = math.log1p(cov**2)
    z = rng.standard_normal(n)
    if correlation > 0.0 and n > 1:
        # z_k = a z_{k-1} + sqrt(1 - a^2) e_k, started at z_0 = e_0: stationary from the first support
        drive = math.sqrt(-math.expm1(2.0 * math.log(correlation))) * z
        drive[0] = z[0]
        z = autoregression(drive, correlation)
    return np.exp(math.sqrt(sigma2) * z - 0.5 * sigma2)


#: Terms of one block of :func:`autoregression`.
_BLOCK = 256


def autoregression(drive: np.ndarray, a: float) -> np.ndarray:
    """``z_k = a z_{k-1} + drive_k`` with ``z_0 = drive_0``, for ``0 <= a < 1``.

    In blocks of :data:`_BLOCK` terms: within a block the sum ``sum_j a^(i-j) drive_j`` is one
    product with a lower-triangular matrix of powers of ``a`` (every coefficient at most 1, so no
    growth of rounding errors), and the blocks are chained by their last terms, one Python step per
    block (scipy.signal.lfilter does the same and costs 0.4 s to import in every worker).

    Parameters
    ----------
    drive : ndarray, shape (n,)
        The input sequence.
    a : float
        The coefficient.

    Returns
    -------
    ndarray, shape (n,)
    """
    n = drive.size
    powers = a ** np.arange(_BLOCK + 1.0)
    lags = np.subtract.outer(np.arange(_BLOCK), np.arange(_BLOCK))
    within = np.where(lags >= 0, powers[np.abs(lags)], 0.0)  # within[i, j] = a^(i - j), j <= i
    padded = np.zeros(-(-n // _BLOCK) * _BLOCK)
    padded[:n] = drive
    z = padded.reshape(-1, _BLOCK) @ within.T  # each block as if it started at rest
    carry = powers[1:]
    for k in range(1, z.shape[0]):  # add what the previous block hands on: a^(i+1) z_last
        z[k] += carry * z[k - 1, -1]
    return z.ravel()[:n]


def _check_seed(seed: object) -> int | tuple[int, ...]:
    """``seed``: a non-negative integer, or a non-empty tuple of them (a study's seed and the realisation)."""
    entries = seed if isinstance(seed, (tuple, list)) else (seed,)
    if not entries or len(entries) > 32:
        raise InputError(f"seed must be a non-negative integer or a tuple of 1 to 32 of them, got {brief(seed)}")
    for i, s in enumerate(entries):
        label = "seed" if entries is not seed else f"seed[{i}]"
        check_int_at_least(label, s, 0)
        if s >= _MAX_SEED:
            raise InputError(f"{label} must be below 2**64, got an integer of {len(str(s))} digits")
    return tuple(int(s) for s in entries) if entries is seed else int(seed)


def _entropy(seed: int | tuple[int, ...]) -> list[int]:
    """The seed as SeedSequence entropy that tells every seed apart: its length, then each entry in
    two 32-bit words (SeedSequence alone joins an int's words and drops trailing zeros, so that
    ``5``, ``(5, 0)`` and ``(5, 0, 0)`` would draw one track)."""
    entries = seed if isinstance(seed, tuple) else (seed,)
    words = [(s >> (32 * j)) & 0xFFFFFFFF for s in entries for j in range(2)]
    return [len(entries) + (0 if isinstance(seed, tuple) else 1000), *words]


def _stream(seed: int | tuple[int, ...], name: str) -> np.random.Generator:
    return np.random.default_rng(np.random.SeedSequence(_entropy(seed), spawn_key=(_STREAMS[name],)))


def _check_cov(cov: object, track: Track) -> dict[str, float]:
    if cov is None:
        return {}
    if not isinstance(cov, Mapping):
        raise InputTypeError(f"cov must be a mapping {{field: coefficient of variation}}, e.g. "
                             f"{{'kv': 0.2, 'kb': 0.3}}, or None, got {brief(cov)}")
    out = {}
    for name, value in cov.items():
        if name not in RANDOM_FIELDS:
            raise InputError(f"cov names {brief(name)}, not a support field; the fields are {RANDOM_FIELDS}")
        if name in _BALLAST_FIELDS and not track.is_ballasted:
            raise InputError(f"cov[{name!r}]: the track has no sleepers on ballast, so no {name} to scatter")
        out[name] = check_in_range(f"cov[{name!r}]", check_real(f"cov[{name!r}]", value), (0.0, MAX_COV),
                                   "a coefficient of variation")
    return {name: out[name] for name in RANDOM_FIELDS if name in out}  # the fixed order of the streams


def _check_voids(voids: object, track: Track) -> tuple[float, tuple[float, float]]:
    """``(fraction, (low, high))`` of ``voids``; ``(0, (0, 0))`` for None."""
    if voids is None:
        return 0.0, (0.0, 0.0)
    if not isinstance(voids, Mapping):
        raise InputTypeError(f"voids must be a mapping such as dict(fraction=0.02, gap=(0.5e-3, 2e-3)), or None, "
                             f"got {brief(voids)}")
    unknown = sorted(map(str, set(voids) - {"fraction", "gap"}))
    if unknown or "fraction" not in voids:
        raise InputError(f"voids takes 'fraction' (required) and 'gap' (m), got keys {sorted(map(str, voids))}")
    if not track.is_ballasted:
        raise InputError("voids: the track has no sleepers on ballast, so none can hang")
    fraction = check_in_range("voids['fraction']", check_real("voids['fraction']", voids["fraction"]), (0.0, 1.0),
                              "a share of the supports")
    gap = voids.get("gap", 1e-3)
    pair = tuple(gap) if isinstance(gap, (tuple, list)) else (gap, gap)
    if len(pair) != 2:
        raise InputError(f"voids['gap'] must be a gap (m) or a range (low, high), got {brief(gap)}")
    low, high = (check_real("voids['gap']", g) for g in pair)
    for g in (low, high):
        if not 0.0 < g <= MAX_GAP:
            raise InputError(f"voids['gap'] must be within (0, {MAX_GAP:g}] m (a gap in mm written as m is 1000 "
                             f"times too large), got {brief(gap)}")
    check_gap("voids['gap']", high)  # within the bound, but above a plausible gap: warned
    if low > high:
        raise InputError(f"voids['gap'] must be a range (low, high) with low <= high, got {brief(gap)}")
    return fraction, (low, high)


@dataclass(frozen=True, eq=False)
class RandomTrack:
    """One realisation of a random track: the drawn support fields, hanging sleepers and failed fasteners.

    Built by :func:`random_track`; it may be built by hand from stored values (each is checked).

    Attributes
    ----------
    track : Track
        The nominal track, whose values are the fields' means.
    first, last : int
        The supports drawn, ``first`` to ``last`` inclusive (support k at ``x = (k + 1/2) d``).
    values : dict of str to ndarray
        Each scattered field's value at every support ``first..last`` (SI units: N/m, N m/rad, kg).
    voided : ndarray of int
        The supports whose sleeper hangs over a gap (ascending).
    gaps : ndarray
        Their gaps (m), in the order of ``voided``.
    failed : ndarray of int
        The supports whose fastener has failed (ascending); none of them voided.
    seed : int or tuple of int
        The seed it was drawn with (None when built by hand).
    """

    track: Track
    first: int
    last: int
    values: dict = field(default_factory=dict)
    voided: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    gaps: np.ndarray = field(default_factory=lambda: np.zeros(0))
    failed: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    seed: object = None

    def __post_init__(self):
        check_fields(self)
        n = len(_supports(self.first, self.last))
        values = {}
        for name, array in self.values.items():
            if name not in RANDOM_FIELDS:
                raise InputError(f"RandomTrack.values names {brief(name)}, not a support field; the fields are "
                                 f"{RANDOM_FIELDS}")
            if name in _BALLAST_FIELDS and not self.track.is_ballasted:
                raise InputError(f"RandomTrack.values[{name!r}]: the track has no sleepers on ballast")
            a = _read_only(np.asarray(array, dtype=float) if _numbers(array) else None,
                           f"RandomTrack.values[{name!r}]")
            if a.shape != (n,) or not (np.isfinite(a).all() and (a > 0).all()):
                raise InputError(f"RandomTrack.values[{name!r}] must hold {n} positive finite values (one per "
                                 f"support first..last = {self.first}..{self.last}), got shape {a.shape}")
            values[name] = a
        object.__setattr__(self, "values", values)
        voided = self._indices("voided", self.voided)
        failed = self._indices("failed", self.failed)
        if np.intersect1d(voided, failed).size:
            raise InputError("RandomTrack.voided and RandomTrack.failed share supports: a failed fastener carries "
                             "no sleeper to hang")
        if voided.size and not self.track.is_ballasted:
            raise InputError("RandomTrack.voided: the track has no sleepers on ballast, so none can hang")
        gaps = _read_only(np.asarray(self.gaps, dtype=float) if _numbers(self.gaps) else None, "RandomTrack.gaps")
        if gaps.shape != voided.shape or not ((gaps > 0) & (gaps <= MAX_GAP)).all():
            raise InputError(f"RandomTrack.gaps must hold one gap within (0, {MAX_GAP:g}] m per voided support "
                             f"({voided.size}), got shape {gaps.shape}")
        object.__setattr__(self, "voided", voided)
        object.__setattr__(self, "failed", failed)
        object.__setattr__(self, "gaps", gaps)
        if self.seed is not None:
            object.__setattr__(self, "seed", _check_seed(self.seed))

    def _indices(self, name: str, value) -> np.ndarray:
        if not _numbers(value) or np.asarray(value).dtype.kind not in "iu" or np.ndim(value) != 1:
            raise InputTypeError(f"RandomTrack.{name} must be a 1-D array of support indices, got {brief(value)}")
        a = np.asarray(value, dtype=np.int64)
        if a.size and (a.min() < self.first or a.max() > self.last or np.unique(a).size != a.size):
            raise InputError(f"RandomTrack.{name} must hold distinct supports from {self.first} to {self.last}, "
                             f"got {brief(value)}")
        return _read_only(np.sort(a), f"RandomTrack.{name}")

    @property
    def supports(self) -> range:
        """The supports drawn, ``first..last``."""
        return range(self.first, self.last + 1)

    @property
    def changes(self) -> dict[int, dict | None]:
        """The ``changes=`` of :class:`semitrack.InfiniteTrack`, :class:`semitrack.TruncatedTrack` and
        :class:`semitrack.WindowTrack`: the drawn fields, ``{"kb": 0.0}`` under a hanging sleeper and
        ``None`` for a failed fastener (supports left nominal are absent)."""
        out: dict[int, dict | None] = {}
        if self.values:
            columns = {name: a.tolist() for name, a in self.values.items()}
            for i, k in enumerate(self.supports):
                out[k] = {name: column[i] for name, column in columns.items()}
        for k in self.voided.tolist():
            out[k] = {**out.get(k, {}), "kb": 0.0}
        for k in self.failed.tolist():
            out[k] = None
        return dict(sorted(out.items()))

    @property
    def ballast_gaps(self) -> dict[int, float]:
        """The ``ballast_gaps=`` of the time-domain runs: ``{support: gap (m)}`` of the hanging sleepers."""
        return dict(zip(self.voided.tolist(), self.gaps.tolist()))

    def table(self):
        """A :class:`pandas.DataFrame`, one row per support: ``support``, ``x`` (m), each drawn field,
        ``void_gap`` (m, 0 where none) and ``failed`` (bool)."""
        import pandas as pd  # only when a table is asked for

        k = np.arange(self.first, self.last + 1)
        gap = np.zeros(k.size)
        gap[self.voided - self.first] = self.gaps
        failed = np.zeros(k.size, bool)
        failed[self.failed - self.first] = True
        return pd.DataFrame({"support": k, "x": (k + 0.5) * self.track.spacing, **self.values, "void_gap": gap,
                             "failed": failed})

    def __repr__(self) -> str:
        fields_ = ", ".join(self.values) or "none"
        return (f"RandomTrack(supports {self.first}..{self.last}, scattered: {fields_}, {self.voided.size} voided, "
                f"{self.failed.size} failed, seed={self.seed!r})")


def _numbers(value) -> bool:
    try:
        return np.asarray(value).dtype.kind in "biuf" and not isinstance(value, (str, bytes))
    except (TypeError, ValueError):
        return False


def _read_only(a: np.ndarray | None, name: str) -> np.ndarray:
    if a is None:
        raise InputTypeError(f"{name} must be numbers")
    a = a.copy()
    a.setflags(write=False)
    return a


def _supports(first: int, last: int) -> range:
    if last < first:
        raise InputError(f"last must be >= first, got first={first}, last={last}")
    if last - first + 1 > MAX_RANDOM_SUPPORTS:
        raise InputError(f"first..last spans {last - first + 1} supports, more than {MAX_RANDOM_SUPPORTS} "
                         f"({MAX_RANDOM_SUPPORTS * 0.6 / 1e3:.0f} km at 0.6 m): draw the stretch a run reaches")
    return range(first, last + 1)


def _chosen(rng: np.random.Generator, pool: np.ndarray, count: int) -> np.ndarray:
    """``count`` supports of ``pool`` without replacement, ascending."""
    return np.sort(rng.choice(pool, size=count, replace=False)) if count else np.zeros(0, np.int64)


def random_track(track: Track, first: int, last: int, *, cov: Mapping[str, float] | None = None,
                 correlation_length: float | None = None, voids: Mapping | None = None, failed: float = 0.0,
                 seed: int | tuple[int, ...] = 0) -> RandomTrack:
    """One realisation of a random track over the supports ``first`` to ``last`` inclusive.

    Parameters
    ----------
    track : Track
        The nominal track: the drawn fields' means, the spacing, whether it has sleepers.
    first, last : int
        The supports drawn (support k at ``x = (k + 1/2) d``); at most :data:`MAX_RANDOM_SUPPORTS`.
    cov : mapping of str to float, optional
        Coefficient of variation (-) per field of :data:`RANDOM_FIELDS`, e.g. ``{"kv": 0.2, "kb": 0.3}``;
        each field log-normal with mean the track's value (the module docstring). None: no scatter.
    correlation_length : float, optional
        Correlation length (m) of the logs of the fields along the track; None: independent supports.
    voids : mapping, optional
        Hanging sleepers: ``dict(fraction=0.02, gap=(0.5e-3, 2e-3))``, a share of the supports
        and a gap (m) or a range to draw it from uniformly (default 1 mm). Ballasted tracks only.
    failed : float
        Share of the supports (not voided) whose fastener has failed, from 0 to 1.
    seed : int or tuple of int
        Seed of the realisation (non-negative); ``(study_seed, i)`` for realisation i of a study.

    Returns
    -------
    RandomTrack
        With ``.changes`` and ``.ballast_gaps`` for the models and runs.

    Examples
    --------
    >>> import semitrack as st
    >>> rt = st.random_track(st.ballasted_track(), -50, 49, cov={"kv": 0.2, "kb": 0.3},
    ...                      voids=dict(fraction=0.05, gap=(0.5e-3, 2e-3)), failed=0.01, seed=(7, 0))
    >>> len(rt.changes), len(rt.ballast_gaps), rt.failed.size
    (100, 5, 1)
    """
    if not isinstance(track, Track):
        raise InputTypeError(f"track must be a semitrack Track, got {brief(track)}")
    first = check_int_at_least("first", first, -10**9)
    last = check_int_at_least("last", last, -10**9)
    if last > 10**9:
        raise InputError(f"last must be an integer <= 1000000000, got {last!r}")
    supports = _supports(first, last)
    cov_ = _check_cov(cov, track)
    correlation = 0.0
    if correlation_length is not None:
        length = check_in_range("correlation_length", check_real("correlation_length", correlation_length),
                                (1e-6, MAX_CORRELATION_LENGTH), "m, along the track")
        correlation = math.exp(-track.spacing / length)
        if correlation >= 1.0:  # a length so long that neighbours are one value in double precision
            raise InputError(f"correlation_length={length:g} m is too long for supports {track.spacing:g} m apart")
    fraction, (low, high) = _check_voids(voids, track)
    failed = check_in_range("failed", check_real("failed", failed), (0.0, 1.0), "a share of the supports")
    seed = _check_seed(seed)
    n = len(supports)
    n_voids, n_failed = round(fraction * n), round(failed * n)
    if n_voids + n_failed > n:
        raise InputError(f"voids['fraction'] and failed together ask for {n_voids + n_failed} of {n} supports")

    values = {name: getattr(track, name) * lognormal_factors(_stream(seed, name), c, n, correlation)
              for name, c in cov_.items() if c > 0.0}
    pool = np.arange(first, last + 1)
    rng = _stream(seed, "voids")
    voided = _chosen(rng, pool, n_voids)
    gaps = rng.uniform(low, high, n_voids)
    failed_ = _chosen(_stream(seed, "failed"), np.setdiff1d(pool, voided), n_failed)
    return RandomTrack(track, first, last, values, voided, gaps, failed_, seed)
