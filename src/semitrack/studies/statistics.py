"""Statistics of a study's table: percentiles with bootstrap confidence intervals, and exceedance.

The results of a Monte Carlo study are samples: a peak force per realisation. What a reader asks
of them is a percentile (the median, the 95th, the 99th) and how sure it is. :func:`percentiles`
gives each percentile with a percentile-bootstrap confidence interval (resampling the cases with
replacement, the same resamples for every percentile, from a seed: reproducible); :func:`exceedance`
gives the empirical probability of exceeding each value, with Weibull's plotting positions
``i / (n + 1)`` so that neither the largest nor the smallest sample sits at probability 0 or 1.
:func:`percentile_table` and :func:`exceedance_table` do the same per group of a column of the table
(the void fraction of each case, say). NaN results (cases that failed) are left out and counted.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..base.checks import brief, check_in_range, check_int_at_least, check_real
from ..base.errors import InputError, InputTypeError

__all__ = ["percentiles", "percentile_table", "exceedance", "exceedance_table", "check_columns", "MAX_BOOTSTRAP",
           "MAX_BOOTSTRAP_WORK"]

#: Most bootstrap resamples.
MAX_BOOTSTRAP = 100_000
#: Most samples a statistic takes (a study's cases).
MAX_SAMPLES = 10_000_000
#: Resampled values held at a time (the bootstrap runs in blocks of at most this many numbers, 16 MB).
_BLOCK = 2_000_000
#: Most values the bootstrap resamples in all (samples x resamples): a few seconds of work.
MAX_BOOTSTRAP_WORK = 500_000_000


def _samples(name: str, values) -> np.ndarray:
    """``values`` as a 1-D float array without its NaNs; refused when empty, not numbers or not finite."""
    if isinstance(values, (str, bytes, bool, np.bool_)) or values is None:
        raise InputTypeError(f"{name} must be numbers (one per case), got {brief(values)}")
    if isinstance(values, np.ma.MaskedArray):  # masked entries are absent, as NaN are
        values = np.ma.filled(values.astype(float), np.nan)
    try:
        a = np.asarray(values)
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} must be a 1-D array of numbers, got a ragged sequence") from None
    if a.dtype.kind not in "biuf" or a.ndim != 1:
        raise InputTypeError(f"{name} must be a 1-D array of numbers, got {brief(values)}")
    if a.size > MAX_SAMPLES:
        raise InputError(f"{name} holds {a.size} samples, more than {MAX_SAMPLES}")
    a = a.astype(float)
    a = a[~np.isnan(a)]
    if not a.size:
        raise InputError(f"{name} holds no numbers (every case failed, or none was given)")
    if not np.isfinite(a).all():
        raise InputError(f"{name} holds infinities: a percentile of them means nothing")
    return a


def _levels(q) -> np.ndarray:
    if isinstance(q, (str, bytes, bool, np.bool_)) or q is None:
        raise InputTypeError(f"q must be percentiles (from 0 to 100), got {brief(q)}")
    try:
        levels = np.atleast_1d(np.asarray(q))
    except (TypeError, ValueError):
        raise InputTypeError("q must be a 1-D sequence of percentiles, got a ragged sequence") from None
    if levels.dtype.kind not in "biuf" or levels.ndim != 1 or not levels.size or levels.size > 100:
        raise InputTypeError(f"q must be 1 to 100 percentiles (from 0 to 100), got {brief(q)}")
    levels = levels.astype(float)
    if not ((levels >= 0) & (levels <= 100)).all():
        raise InputError(f"q must be percentiles from 0 to 100, got {brief(q)}")
    return levels


def percentiles(values, q: Sequence[float] = (50.0, 95.0, 99.0), *, confidence: float = 0.95, n_boot: int = 2000,
                seed: int = 0):
    """Percentiles of samples with percentile-bootstrap confidence intervals.

    Parameters
    ----------
    values : array_like, 1-D
        The samples (one per case); NaNs (failed cases) are left out.
    q : sequence of float
        Percentiles (0-100).
    confidence : float
        Level of the interval, from 0.5 to 0.999.
    n_boot : int
        Bootstrap resamples (100 to :data:`MAX_BOOTSTRAP`).
    seed : int
        Seed of the resampling.

    Returns
    -------
    pandas.DataFrame
        One row per percentile: ``q``, ``value`` (of the samples, linear interpolation), ``low`` and
        ``high`` (the interval), ``n`` (samples used).

    Examples
    --------
    >>> t = percentiles(np.arange(1.0, 101.0), [50])
    >>> float(t.value[0]), bool(t.low[0] < 50.5 < t.high[0])
    (50.5, True)
    """
    import pandas as pd

    a = _samples("values", values)
    levels = _levels(q)
    confidence = check_in_range("confidence", check_real("confidence", confidence), (0.5, 0.999), "a probability")
    n_boot = check_int_at_least("n_boot", n_boot, 100)
    if n_boot > MAX_BOOTSTRAP:
        raise InputError(f"n_boot must be at most {MAX_BOOTSTRAP}, got {n_boot}")
    seed = check_int_at_least("seed", seed, 0)
    if a.size * n_boot > MAX_BOOTSTRAP_WORK:
        raise InputError(f"n_boot={n_boot} resamples of {a.size} values is more work than {MAX_BOOTSTRAP_WORK:.0e} "
                         "values: ask for fewer resamples (the intervals of thousands of cases settle with 1000)")
    rng = np.random.default_rng(seed)
    rows = max(1, _BLOCK // a.size)
    boot = np.empty((levels.size, n_boot))
    for start in range(0, n_boot, rows):  # blocks of resamples: bounded memory for any sample size
        stop = min(n_boot, start + rows)
        boot[:, start:stop] = np.percentile(a[rng.integers(0, a.size, (stop - start, a.size))], levels, axis=1)
    tail = 50.0 * (1.0 - confidence)
    low, high = np.percentile(boot, [tail, 100.0 - tail], axis=1)
    return pd.DataFrame({"q": levels, "value": np.percentile(a, levels), "low": low, "high": high, "n": a.size})


def exceedance(values):
    """The empirical probability of exceeding each sample (Weibull's plotting positions).

    Parameters
    ----------
    values : array_like, 1-D
        The samples; NaNs are left out.

    Returns
    -------
    pandas.DataFrame
        ``value`` in ascending order and ``exceedance``, ``1 - i / (n + 1)`` for the i-th smallest.

    Examples
    --------
    >>> exceedance([3.0, 1.0, 2.0]).exceedance.tolist()
    [0.75, 0.5, 0.25]
    """
    import pandas as pd

    a = np.sort(_samples("values", values))
    return pd.DataFrame({"value": a, "exceedance": 1.0 - np.arange(1, a.size + 1) / (a.size + 1)})


def check_columns(table, **names) -> None:
    """``table`` a DataFrame holding every column named (``{argument: column or None}``)."""
    if type(table).__name__ != "DataFrame":
        raise InputTypeError(f"table must be a study's pandas DataFrame (st.run_study), got {brief(table)}")
    for label, name in names.items():
        if name is not None and (not isinstance(name, str) or name not in table.columns):
            raise InputError(f"{label}={brief(name)} is not a column of the table; its columns are "
                             f"{list(map(str, table.columns))[:20]}")


def _groups(table, column: str, by: str | None):
    """``[(group value, samples)]`` of ``table[column]``, grouped by ``table[by]`` (sorted) or whole."""
    check_columns(table, column=column, by=by)
    if by is None:
        return [(None, table[column].to_numpy())]
    return [(value, part[column].to_numpy()) for value, part in table.groupby(by, sort=True, dropna=False)]


def _per_group(statistic, table, column: str, by: str | None, **options):
    """``statistic`` of each group's samples, led by the group's value; a group with no numbers named."""
    import pandas as pd

    parts = []
    for value, samples in _groups(table, column, by):
        try:
            part = statistic(samples, **options)
        except InputError as err:
            where = "" if by is None else f" where {by} = {value!r}"
            raise InputError(f"column {column!r}{where}: {err}") from None
        if by is not None:
            part.insert(0, by, value)
        parts.append(part)
    return pd.concat(parts, ignore_index=True)


def percentile_table(table, column: str, by: str | None = None, q: Sequence[float] = (50.0, 95.0, 99.0), *,
                     confidence: float = 0.95, n_boot: int = 2000, seed: int = 0):
    """:func:`percentiles` of a study's column, per value of another.

    Parameters
    ----------
    table : pandas.DataFrame
        A study's table (:func:`semitrack.run_study`).
    column : str
        The result (e.g. ``"peak_force"``).
    by : str, optional
        The input to group by (e.g. ``"void_fraction"``; NaN is a group of its own); None: all cases.
    q, confidence, n_boot, seed
        As :func:`percentiles` (every group resampled from ``seed``).

    Returns
    -------
    pandas.DataFrame
        :func:`percentiles`' columns, led by ``by`` when given.
    """
    return _per_group(percentiles, table, column, by, q=q, confidence=confidence, n_boot=n_boot, seed=seed)


def exceedance_table(table, column: str, by: str | None = None):
    """:func:`exceedance` of a study's column, per value of another (``by`` leads the columns)."""
    return _per_group(exceedance, table, column, by)
