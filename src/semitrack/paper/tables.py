"""The book's comparison tables: the paper's values beside ours, and the errors of equivalent systems.

Each builder returns a numeric :class:`pandas.DataFrame`; the slab and ballasted chapters and the
validation chapter call the same builders, so a table is computed one way only. Errors are
relative (the complex ``|approx - reference| / |reference|``) and given in per cent; each table
names its measure (the "element error" of :func:`semitrack.error_summary`, the "worst-element
error", the "junction error") in its column names and caption.

:func:`styled` formats a table for a reader at display time, without touching its values: one
format per column (a builder stores its own in ``table.attrs["formats"]``), "–" for a missing
value, no 0..N index, and the caption of ``table.attrs["caption"]``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, check_band
from ..base.errors import InputError
from ..base.paper_values import TABLE2_SLAB, TABLE5_BALLASTED
from ..equivalent.metrics import ELEMENT_ERROR, error_band_grid, error_summary
from ..equivalent.systems import EquivalentSystem
from ..methods.receptance import CentralResponse, central_response, semi_infinite_receptance
from ..model.tracks import PARAMETER_INFO, Track, parameter_table, require_track
from .convergence import alpha_relative_error
from .systems import PAPER_FREQUENCIES, paper_table7, table4_consistency, table7_consistency

__all__ = ["FIT_ERROR_TARGETS", "MISSING", "MirroredPair", "fit_error_table", "inversion_error_table", "listed",
           "fixed", "mirrored_pair", "mirrored_pair_table", "parameter_comparison", "readable_number", "styled",
           "system_comparison", "table4_consistency_table", "table7_consistency_table"]

#: What :func:`styled` shows for a missing (NaN) value.
MISSING = "–"

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


# --- display ------------------------------------------------------------------------------------
def listed(values: Mapping, fmt: str = "{:.3g}", unit: str = "") -> str:
    """A mapping as a reader's line, ``"slab 0.228 dB; ballasted 0.201 dB"``: no reprs, no braces.

    Parameters
    ----------
    values : mapping
        Name to a number, or to a sequence of numbers (written with ", ").
    fmt : str
        Format of each number.
    unit : str
        Written after each value ("" for none).

    Returns
    -------
    str

    Examples
    --------
    >>> listed({"slab": 0.2281, "ballasted": [1.0, 2.5]}, "{:.2f}", "dB")
    'slab 0.23 dB; ballasted 1.00, 2.50 dB'
    """
    def one(value) -> str:
        if isinstance(value, (list, tuple, np.ndarray)):
            return ", ".join(fmt.format(float(v)) for v in value)
        return fmt.format(float(value))

    return "; ".join(f"{name} {one(value)}{' ' + unit if unit else ''}" for name, value in values.items())


def readable_number(x: float, digits: int = 4) -> str:
    """``x`` with ``digits`` significant digits, exact trailing zeros dropped, powers of ten written out.

    Parameters
    ----------
    x : float
        The number.
    digits : int
        Significant digits (>= 1).

    Returns
    -------
    str
        Plain between 1e-3 and 1e5 (``7850``, ``0.25``), else ``2.1×10¹¹``; trailing zeros
        are kept where they are significant (``19.00`` for 19.003); ``0`` for zero,
        :data:`MISSING` for NaN, ``∞`` for infinity.

    Examples
    --------
    >>> [readable_number(v) for v in (7850.0, 2.1e11, 0.25, 3.055e-5, -0.0123456, 19.003)]
    ['7850', '2.1×10¹¹', '0.25', '3.055×10⁻⁵', '-0.01235', '19.00']
    """
    if math.isnan(x):
        return MISSING
    if math.isinf(x):
        return "∞" if x > 0 else "-∞"
    if x == 0:
        return "0"
    exponent = math.floor(math.log10(abs(x)))
    if -3 <= exponent < 5:
        return _exact_trimmed(f"{x:.{max(digits - 1 - exponent, 0)}f}", x)
    mantissa, power = f"{x:.{digits - 1}e}".split("e")
    mantissa = _exact_trimmed(mantissa, x / 10 ** int(power))
    return f"{mantissa}×10{str(int(power)).translate(_SUPERSCRIPT)}"


def _exact_trimmed(text: str, x: float) -> str:
    """``text`` without trailing zeros when they are exact (0.2500 of 0.25), else as it is (19.00 of 19.003)."""
    if "." not in text:
        return text
    trimmed = text.rstrip("0").rstrip(".")
    return trimmed if math.isclose(float(trimmed), x, rel_tol=1e-12) else text


def fixed(decimals: int) -> Callable[[float], str]:
    """A formatter with ``decimals`` decimals that writes a rounded-off zero as ``0.00``, not ``-0.00``.

    Parameters
    ----------
    decimals : int
        Digits after the point.
    """
    def format_fixed(x: float) -> str:
        text = f"{x:.{decimals}f}"
        return text.lstrip("-") if float(text) == 0 else text
    return format_fixed


def _default_format(label, values: pd.Series) -> Callable | str | None:
    """Per cent and hertz columns (or rows) with two decimals, other floats by :func:`readable_number`."""
    if pd.api.types.is_bool_dtype(values) or not pd.api.types.is_float_dtype(values):
        return None
    text = " ".join(map(str, label)) if isinstance(label, tuple) else str(label)
    return fixed(2) if text.endswith(("(%)", "(Hz)")) else readable_number


def styled(table: pd.DataFrame, formats: Mapping | None = None, *, index: bool = False,
           caption: str | None = None, by_row: bool = False):
    """``table`` formatted for a reader (a pandas Styler); the values stay as they are.

    Parameters
    ----------
    table : pandas.DataFrame
        The table; ``table.attrs["formats"]`` and ``table.attrs["caption"]`` (set by the
        builders of this module) give its formats and caption unless overridden here.
    formats : mapping, optional
        Format per column (or per row with ``by_row``): a format string such as ``"{:.1f}"`` or
        a callable. Float columns without one: two decimals when the label ends in ``(%)`` or
        ``(Hz)``, else :func:`readable_number`.
    index : bool
        Show the index (for a meaningful one, e.g. parameter names); default hidden. Float
        levels of a shown index are written by :func:`readable_number`.
    caption : str, optional
        A caption, e.g. the definition of the error measure.
    by_row : bool
        ``formats`` are keyed by the index (a transposed table: one quantity per row); also
        set by ``table.attrs["by_row"]``.

    Returns
    -------
    pandas.io.formats.style.Styler
        NaN shown as :data:`MISSING`.
    """
    formats = {**table.attrs.get("formats", {}), **(formats or {})}
    by_row = by_row or table.attrs.get("by_row", False)
    style = table.style.format(na_rep=MISSING)
    for label in table.index if by_row else table.columns:
        values = table.loc[label] if by_row else table[label]
        fmt = formats.get(label, _default_format(label, values))
        if fmt is not None:
            subset = pd.IndexSlice[[label], :] if by_row else [label]
            style = style.format(fmt, subset=subset, na_rep=MISSING)
    if not index:
        style = style.hide(axis="index")
    for level in range(table.index.nlevels) if index else ():
        if pd.api.types.is_float_dtype(table.index.get_level_values(level)):
            style = style.format_index(readable_number, axis="index", level=level)
    caption = caption if caption is not None else table.attrs.get("caption")
    return style.set_caption(caption) if caption else style

#: The two receptances an equivalent system is judged against in :func:`fit_error_table`.
FIT_ERROR_TARGETS = ("exact alpha", "paper's-method alpha")


def parameter_comparison(track: Track) -> pd.DataFrame:
    """The track's parameters beside the paper's Table 2 (slab) or Tables 2 and 5 (ballasted).

    Parameters
    ----------
    track : Track
        A slab track (compared with Table 2) or a ballasted track (Tables 2 and 5).

    Returns
    -------
    pandas.DataFrame
        :func:`semitrack.parameter_table` with two more columns: ``paper (Table 2)`` or
        ``paper (Tables 2, 5)`` (SI units) and ``deviation (%)``.
    """
    track = require_track(track)
    track.require_constant("the comparison with the paper's constant parameters",
                           "compare the curve with the paper's value at the frequencies of interest instead")
    paper, label = (TABLE5_BALLASTED, "paper (Tables 2, 5)") if track.is_ballasted else (TABLE2_SLAB, "paper (Table 2)")
    key_of = {symbol: key for key, symbol, _, _ in PARAMETER_INFO}
    table = parameter_table(track)
    table[label] = [paper[key_of[symbol]] for symbol in table["symbol"]]
    table["deviation (%)"] = 100 * (table["value"] / table[label] - 1)
    table.attrs["formats"] = {"deviation (%)": readable_number}  # an exact 0 reads "0", not a rounded "0.00"
    return table


def system_comparison(paper: EquivalentSystem, ours: EquivalentSystem, paper_label: str) -> pd.DataFrame:
    """Two equivalent systems' parameters side by side (one row per parameter, one column per bar).

    Parameters
    ----------
    paper, ours : EquivalentSystem
        The paper's system (e.g. ``st.paper_table4()``) and another one of the same layout.
    paper_label : str
        Column group of the paper's system, e.g. ``"paper (Table 4)"``; the other is ``"ours"``.

    Returns
    -------
    pandas.DataFrame
        Columns ``(paper_label, "bar j")`` and ``("ours", "bar j")``; units in the row names
        (show it with ``styled(table, index=True)``).
    """
    table = pd.concat({paper_label: paper.to_frame(), "ours": ours.to_frame()}, axis=1)
    table.attrs["caption"] = (f"The hinge parameters k_phi, c_phi between bar j and bar j+1 are listed under "
                              f"bar j; {MISSING}: no hinge after the last bar.")
    return table


def _wavenumber_alpha(track: Track, f: np.ndarray, known: CentralResponse | None) -> np.ndarray:
    """The paper's-method alpha at ``f``, taken from ``known`` where it holds the frequency."""
    if known is None:
        return semi_infinite_receptance(track, f, method="wavenumber")
    if not isinstance(known, CentralResponse) or known.method != "wavenumber":
        raise InputError("wavenumber_response must be a CentralResponse of method='wavenumber', got "
                         f"{getattr(known, 'method', type(known).__name__)!r}")
    order = np.argsort(known.f, kind="stable")
    pos = order[np.searchsorted(known.f[order], f).clip(0, known.f.size - 1)]
    have = known.f[pos] == f
    alpha = np.empty((f.size, 2, 2), dtype=complex)
    if np.any(have):
        alpha[have] = known.alpha[pos[have]]
        first = int(np.flatnonzero(have)[0])
        if not np.allclose(semi_infinite_receptance(track, f[first:first + 1], method="wavenumber")[0],
                           alpha[first], rtol=1e-12, atol=0):
            raise InputError(f"wavenumber_response is not this track's paper-method sweep (it differs at "
                             f"{f[first]:g} Hz); pass central_response(track, f, method='wavenumber')")
    if np.any(~have):
        alpha[~have] = semi_infinite_receptance(track, f[~have], method="wavenumber")
    return alpha


def fit_error_table(track: Track, systems: Mapping[str, EquivalentSystem], band: tuple[float, float],
                    df: float = 3.0, wavenumber_response: CentralResponse | None = None) -> pd.DataFrame:
    """Median and maximum error of equivalent systems against the track over a band.

    Each system's receptance is compared on the grid of :func:`semitrack.error_band_grid` with
    the exact receptance and with the paper's-method (wavenumber) receptance of the track; the
    error is that of :func:`semitrack.error_summary` (elements alpha11, alpha12, alpha22).

    Parameters
    ----------
    track : Track
        The track.
    systems : mapping of str to EquivalentSystem
        The systems to judge, by label.
    band : tuple of float
        ``(f_lo, f_hi)`` (Hz), e.g. ``FIT_BANDS["slab"]``.
    df : float
        Grid step (Hz).
    wavenumber_response : CentralResponse, optional
        A sweep of this track by the paper's method with its settings
        (``central_response(track, f, method="wavenumber")``, e.g. the chapter's sweep over
        ``PAPER_GRID``): its alpha is used at the grid frequencies it holds (half of a 3 Hz grid
        lies on the paper's 6 Hz grid), and only the others are computed (the method is
        per-frequency, so the numbers are the same). One shared frequency is recomputed to
        check that it is this track's: a ValueError otherwise.

    Returns
    -------
    pandas.DataFrame
        Columns ``system, against, median element error (%), max element error (%)``;
        ``against`` is one of :data:`FIT_ERROR_TARGETS`; the caption defines the measure.
    """
    band = check_band(band)
    grid = error_band_grid(band, df=df)
    targets = dict(zip(FIT_ERROR_TARGETS, (semi_infinite_receptance(require_track(track), grid),
                                           _wavenumber_alpha(track, grid, wavenumber_response))))
    rows = []
    for label, system in systems.items():
        approx = system.receptance(grid)
        for against, target in targets.items():
            e = error_summary(approx, target)
            rows.append((label, against, 100 * e.median, 100 * e.max))
    table = pd.DataFrame(rows, columns=["system", "against", f"median {ELEMENT_ERROR} (%)", f"max {ELEMENT_ERROR} (%)"])
    table.attrs["formats"] = dict.fromkeys(table.columns[2:], "{:.1f}")
    table.attrs["caption"] = (f"{ELEMENT_ERROR.capitalize()}: |α_E − α|/|α| of α11, α12 and α22 at every "
                              f"frequency of a {grid[1] - grid[0]:.3g} Hz grid over {band[0]:g}-{band[1]:g} Hz; "
                              "median and maximum over all elements and frequencies together.")
    return table


@dataclass(frozen=True)
class MirroredPair:
    """The paper's Sec. 5.3 check of equivalent systems on one track.

    Attributes
    ----------
    f : ndarray
        Frequencies (Hz).
    w1 : ndarray
        The complete track's central receptance (m/N), exact method.
    joined : dict of str to ndarray
        Each system's vertical receptance at the junction of it and its mirror image (m/N).
    errors : dict of str to ndarray
        ``|joined - w1| / |w1|`` per system (-).
    band : tuple of float
        The band the systems were fitted over (Hz).
    """

    f: np.ndarray
    w1: np.ndarray
    joined: dict
    errors: dict
    band: tuple

    def summary(self) -> list[tuple]:
        """Rows ``(system, band text, median error (%), max error (%))`` over :attr:`band`."""
        inside = (self.f >= self.band[0]) & (self.f <= self.band[1])
        text = f"{self.band[0]:g}-{self.band[1]:g}"
        return [(label, text, 100 * np.median(e[inside]), 100 * e[inside].max()) for label, e in self.errors.items()]


def mirrored_pair(track: Track, systems: Mapping[str, EquivalentSystem], f: ArrayLike,
                  band: tuple[float, float]) -> MirroredPair:
    """Receptance at the junction of two mirrored copies of each system against the track's w1.

    Parameters
    ----------
    track : Track
        The track; its central receptance w1 (exact method) is the reference.
    systems : mapping of str to EquivalentSystem
        The systems, by label.
    f : array_like
        Frequencies (Hz), 1-D.
    band : tuple of float
        The fitted band (Hz), over which :meth:`MirroredPair.summary` takes its statistics.

    Returns
    -------
    MirroredPair
    """
    f = as_frequencies(f)
    w1 = central_response(require_track(track), f).w1
    joined = {label: system.mirrored_receptance(f)[:, 0, 0] for label, system in systems.items()}
    errors = {label: np.abs(w - w1) / np.abs(w1) for label, w in joined.items()}
    return MirroredPair(f=f, w1=w1, joined=joined, errors=errors, band=check_band(band))


def mirrored_pair_table(pairs: Mapping[str, MirroredPair]) -> pd.DataFrame:
    """The errors of :func:`mirrored_pair` for several tracks as one table.

    Parameters
    ----------
    pairs : mapping of str to MirroredPair
        The results, by track label.

    Returns
    -------
    pandas.DataFrame
        Columns ``track, system, band (Hz), median junction error (%), max junction error (%)``;
        the caption defines the measure.
    """
    rows = [(name, *row) for name, pair in pairs.items() for row in pair.summary()]
    table = pd.DataFrame(rows, columns=["track", "system", "band (Hz)", "median junction error (%)",
                                        "max junction error (%)"])
    table.attrs["formats"] = dict.fromkeys(table.columns[3:], "{:.1f}")
    table.attrs["caption"] = ("Junction error: |w_E − w̃1|/|w̃1|, the vertical receptance at the junction of a "
                              "system and its mirror image against the complete track's, over the fitted band.")
    return table


def inversion_error_table(track: Track, systems: Mapping[str, EquivalentSystem], band: tuple[float, float],
                          df: float = 3.0) -> pd.DataFrame:
    """How relative errors of alpha grow in K = alpha^-1, the quantity the mirrored pair measures.

    Parameters
    ----------
    track : Track
        The track (exact receptance as the reference).
    systems : mapping of str to EquivalentSystem
        The systems, by label.
    band : tuple of float
        ``(f_lo, f_hi)`` (Hz).
    df : float
        Grid step (Hz), as for :func:`fit_error_table`.

    Returns
    -------
    pandas.DataFrame
        One row per system: ``system``; the median and maximum over the band of
        ``|a11 a22| / |det a|`` (-) of the track; the median element error of alpha (%, as in
        :func:`fit_error_table`), the median worst-element error of alpha (%, at each frequency
        the largest element error, :func:`semitrack.paper.convergence.alpha_relative_error`) and
        the median relative error of K11 (%).
    """
    band = check_band(band)
    grid = error_band_grid(band, df=df)
    alpha = semi_infinite_receptance(require_track(track), grid)
    amplification = np.abs(alpha[:, 0, 0] * alpha[:, 1, 1]) / np.abs(np.linalg.det(alpha))
    k11_ref = np.linalg.inv(alpha)[:, 0, 0]
    rows = []
    for label, system in systems.items():
        approx = system.receptance(grid)
        err_k11 = np.abs(np.linalg.inv(approx)[:, 0, 0] - k11_ref) / np.abs(k11_ref)
        rows.append((label, np.median(amplification), np.max(amplification), 100 * error_summary(approx, alpha).median,
                     100 * np.median(alpha_relative_error(approx, alpha)), 100 * np.median(err_k11)))
    table = pd.DataFrame(rows, columns=["system", "median |α11 α22|/|det α| (-)", "max |α11 α22|/|det α| (-)",
                                        f"median {ELEMENT_ERROR} of α (%)", "median worst-element error of α (%)",
                                        "median error of K11 (%)"])
    table.attrs["formats"] = dict.fromkeys(table.columns[1:3], "{:.2f}")
    # The caption leaves the band out, so that tables of several bands concatenated keep it.
    table.attrs["caption"] = (f"Over the band on a {grid[1] - grid[0]:.3g} Hz grid. Element error: all elements "
                              "and frequencies pooled; worst-element error: at each frequency the largest element "
                              "error; error of K11 = (α⁻¹)11: |K_E,11 − K11|/|K11|.")
    return table


# --- consistency of the paper's printed systems with its constraints ----------------------------
_ROUNDING_NOTE = ("deviation: (printed - relation) / relation; rounding bound: the largest deviation that "
                  "rounding to the printed digits explains.")


def table4_consistency_table(f_n: float = PAPER_FREQUENCIES["f_n_slab"]) -> pd.DataFrame:
    """Table 4 against Eq. (19)-(20), one row per bar (:func:`~.systems.table4_consistency`).

    Parameters
    ----------
    f_n : float
        The first resonance of the semi-infinite slab track in Eq. (19) (Hz); the paper's 183 Hz.

    Returns
    -------
    pandas.DataFrame
        Columns ``bar``, ``m (kg)``, printed ``k`` and ``J``, their values by Eq. (19)/(20), the
        deviations and rounding bounds (%), and the bounce and pitch frequencies the printed
        numbers imply (Hz; also the unit cell's two natural frequencies). NaN for the massless
        bars, which have nothing to check.
    """
    c = table4_consistency(f_n)
    table = pd.DataFrame({
        "bar": c["bar"], "m (kg)": c["m"],
        "k printed (N/m)": c["k_printed"], "k by Eq. (19) (N/m)": c["k_eq19"],
        "k deviation (%)": 100 * c["k_rel_dev"], "k rounding bound (%)": 100 * c["k_rounding"],
        "J printed (kg m²)": c["J_printed"], "J by Eq. (20) (kg m²)": c["J_eq20"],
        "J deviation (%)": 100 * c["J_rel_dev"], "J rounding bound (%)": 100 * c["J_rounding"],
        "bounce √(2k/m)/2π (Hz)": c["f_bounce_implied"], "pitch √(kL²/2J)/2π (Hz)": c["f_pitch_implied"],
    })
    table.attrs["formats"] = {label: fixed(3) for label in table.columns if label.endswith("(%)")}
    table.attrs["caption"] = (f"Eq. (19)-(20) at f_n = {f_n:g} Hz; {_ROUNDING_NOTE} {MISSING}: massless bar "
                              "(m = J = k = 0), nothing to check.")
    return table


def table7_consistency_table(f_n1: float = PAPER_FREQUENCIES["f_n1"],
                             f_n2_candidates: tuple[float, ...] = (PAPER_FREQUENCIES["f_n2_stated"],
                                                                   PAPER_FREQUENCIES["f_n2_peak"]),
                             f_anti: float = PAPER_FREQUENCIES["f_anti"]) -> pd.DataFrame:
    """Table 7 against Eq. (23), (28)-(30): one quantity per row, one bar per column.

    Parameters
    ----------
    f_n1 : float
        omega_n1 / 2 pi of Eq. (29)-(30) (Hz); the paper's 117 Hz.
    f_n2_candidates : tuple of float
        The values of omega_n2 / 2 pi to test (Hz); the paper's 465 and 489 Hz.
    f_anti : float
        omega_anti / 2 pi of Eq. (23) (Hz); the paper's 243 Hz.

    Returns
    -------
    pandas.DataFrame
        Rows named with their units (from :func:`~.systems.table7_consistency`): ``J`` and
        ``mu`` printed and by their relations, the deviations of ``k`` and ``s`` for each
        candidate, the rounding bounds (%), the frequencies the printed numbers imply (Hz),
        ``s`` printed and the ``s`` that makes Eq. (23) exact (N/m), and the unit cells'
        natural frequencies (Hz). Columns ``bar 1`` ... ``bar N``. Show it with
        ``styled(table, index=True)`` (formats by row).
    """
    c = table7_consistency(f_n1=f_n1, f_n2_candidates=f_n2_candidates, f_anti=f_anti)
    rows = {"J printed (kg m²)": c["J_printed"], "J by Eq. (28) (kg m²)": c["J_eq28"],
            "J deviation (%)": 100 * c["J_rel_dev"], "J rounding bound (%)": 100 * c["J_rounding"],
            "μ printed (kg)": c["mu_printed"], "μ by Eq. (23) (kg)": c["mu_eq23"],
            "μ deviation (%)": 100 * c["mu_rel_dev"], "μ rounding bound (%)": 100 * c["mu_rounding"]}
    for name, equation in (("k", "29"), ("s", "30")):
        for f2 in f_n2_candidates:
            rows[f"{name} deviation from Eq. ({equation}), f_n2 = {f2:g} Hz (%)"] = 100 * c[f"{name}_rel_dev_{f2:g}"]
        rows[f"{name} rounding bound (%)"] = 100 * c[f"{name}_rounding"]
    rows.update({"f_n2 implied by k, Eq. (29) (Hz)": c["f_n2_from_k"],
                 "f_n2 implied by s, Eq. (30) (Hz)": c["f_n2_from_s"],
                 "f_anti implied by μ, Eq. (23) (Hz)": c["f_anti_from_mu"],
                 "s printed (N/m)": paper_table7().s, "s making Eq. (23) exact (N/m)": c["s_from_mu"]})
    rows.update({f"unit-cell frequency {i} (Hz)": c[f"cell_f{i}"] for i in range(1, 5)})
    table = pd.DataFrame.from_dict(rows, orient="index", columns=[f"bar {j}" for j in c["bar"]])
    table.attrs["by_row"] = True
    table.attrs["caption"] = (f"Relations at f_n1 = {f_n1:g} Hz and f_anti = {f_anti:g} Hz; {_ROUNDING_NOTE}")
    return table
