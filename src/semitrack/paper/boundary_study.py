"""The broadband boundary beside the paper's N = 5 end systems, over 3 Hz - 3 kHz.

The computations of the book's chapter "Beyond the pinned-pinned frequency": each function
returns a table (:class:`pandas.DataFrame`) or arrays that the chapter displays or draws with
:mod:`semitrack.plotting`, so the notebook only calls them.

* What the ends are judged on: the element-wise relative error of ``alpha`` over frequency bands
  (:func:`band_errors`, :func:`error_curves`, :func:`receptance_curves`), the limits a boundary
  pins (:func:`limits_table`) and its error against its order (:func:`order_study`).
* Why a hysteretic track cannot be matched closely: the best passive relaxation (Maxwell)
  model of a spring with a constant loss factor (:func:`maxwell_loss_bound`,
  :func:`causality_table`).
* The passivity margin on a frequency grid (:func:`passivity_margin`); the proof itself is the
  Hamiltonian test of :mod:`semitrack.boundary.passivity`.
* The ends in use: 10-bay truncated tracks in the frequency domain (:func:`compared_boundary_ends`,
  :func:`w1_error_table`) and a broadband pulse in the time domain (:func:`pulse_study`,
  :func:`pulse_error_table`).
* The paper's open problem in the paper's own form: the broadband end as M, C, K
  (:func:`mck_summary`) beside the paper's system under the same pulse (:func:`mck_pulse_study`).

Errors are relative (``|approx - reference| / |reference|``); tables give them in per cent.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike
from scipy.optimize import linprog

from ..base.checks import as_frequencies, check_band, check_int_at_least, check_positive
from ..base.conventions import ELEMENTS, EXACT_LABEL
from ..boundary.fitting import BroadbandBoundary, fit_boundary, track_end_limits
from ..equivalent.metrics import error_band_grid, error_summary, receptance_errors
from ..equivalent.systems import EquivalentSystem
from ..fe.ends import EXACT, PINNED, BoundaryEnd, EquivalentEnd
from ..fe.truncation import relative_l2_error, truncation_errors
from ..methods.receptance import semi_infinite_receptance
from ..model.tracks import Track, ballasted_track, require_track, slab_track

__all__ = ["STUDY_BAND", "study_tracks", "boundary_summary", "passivity_table", "route_comparison",
           "band_errors", "error_curves", "receptance_curves", "limits_table", "order_study", "LossFactorBound",
           "maxwell_loss_bound", "causality_table", "passivity_margin", "compared_boundary_ends", "w1_error_table",
           "pulse_study", "pulse_error_table", "mck_summary", "mck_pulse_study"]

#: The band of the broadband boundary (Hz): from the paper's lowest frequency to 3 kHz.
STUDY_BAND = (3.0, 3000.0)


def _band_text(band: tuple[float, float]) -> str:
    """``"lo-hi Hz"`` for a band given in Hz."""
    return f"{band[0]:g}-{band[1]:g} Hz"


def study_tracks() -> dict[tuple[str, str], Track]:
    """The paper's two tracks with their hysteretic loss factors and with causal viscous damping.

    Returns
    -------
    dict
        ``{(track, damping): Track}`` for track in ("slab", "ballasted") and damping in
        ("hysteretic", "viscous"); the viscous dampers equal the loss factors at each family's
        reference frequency (:meth:`semitrack.Track.reference_frequencies`, Hz).

    Examples
    --------
    >>> sorted(study_tracks())[0]
    ('ballasted', 'hysteretic')
    """
    return {(name, damping): preset(damping=damping)
            for damping in ("hysteretic", "viscous")
            for name, preset in (("slab", slab_track), ("ballasted", ballasted_track))}


def boundary_summary(boundaries: Mapping[tuple, BroadbandBoundary],
                     targets: Mapping[tuple, tuple[float, float]] | None = None) -> pd.DataFrame:
    """The fitted boundaries at a glance, with the error targets set for them.

    Parameters
    ----------
    boundaries : mapping of tuple to BroadbandBoundary
        ``{(track, damping): boundary}``.
    targets : mapping of tuple to (float, float), optional
        ``{(track, damping): (median, max)}`` targets of the errors (%); NaN leaves one out.

    Returns
    -------
    pandas.DataFrame
        Indexed by (track, damping); columns ``n_poles``, ``states``, ``median error (%)``,
        ``max error (%)``, ``proven passive``, ``enforcement rounds``, ``fit time (s)`` and, with
        ``targets``, ``target median (%)``, ``target max (%)`` and ``targets met``.
    """
    rows = {}
    for key, b in boundaries.items():
        rows[key] = {"n_poles": b.n_poles, "states": b.state_space().n_states, "median error (%)": 100 * b.median_error,
                     "max error (%)": 100 * b.max_error, "proven passive": bool(b.is_passive()),
                     "enforcement rounds": b.enforcement_rounds, "fit time (s)": b.elapsed}
        if targets is not None:
            med, top = targets.get(key, (np.nan, np.nan))
            rows[key].update({"target median (%)": med, "target max (%)": top, "targets met": bool(
                not 100 * b.median_error > med and not 100 * b.max_error > top)})  # NaN targets always met
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index = pd.MultiIndex.from_tuples(table.index, names=["track", "damping"])
    return table


def passivity_table(boundaries: Mapping[tuple, BroadbandBoundary]) -> pd.DataFrame:
    """The exact (Hamiltonian) passivity test of each boundary, re-run.

    Parameters
    ----------
    boundaries : mapping of tuple to BroadbandBoundary
        ``{(track, damping): boundary}``.

    Returns
    -------
    pandas.DataFrame
        Indexed by (track, damping); columns ``stable``, ``imaginary-axis crossings`` (their
        number), ``proven passive``, ``smallest eigenvalue (-)``, ``at (Hz)`` and
        ``enforcement rounds``.
    """
    rows = {}
    for key, b in boundaries.items():
        r = b.is_passive()
        rows[key] = (r.stable, len(r.crossings_hz), bool(r), r.worst_eigenvalue, r.worst_frequency_hz,
                     b.enforcement_rounds)
    table = pd.DataFrame.from_dict(rows, orient="index", columns=[
        "stable", "imaginary-axis crossings", "proven passive", "smallest eigenvalue (-)", "at (Hz)",
        "enforcement rounds"])
    table.index = pd.MultiIndex.from_tuples(table.index, names=["track", "damping"])
    return table


def route_comparison(tracks: Mapping[str, Track], systems: Mapping[str, EquivalentSystem],
                     boundaries: Mapping[str, BroadbandBoundary], bands: Mapping[str, tuple[float, float]],
                     df: float = 3.0) -> pd.DataFrame:
    """The N = 5 route and the broadband boundary side by side, per track.

    Parameters
    ----------
    tracks : mapping of str to Track
        Tracks by name.
    systems : mapping of str to EquivalentSystem
        Each track's N = 5 system.
    boundaries : mapping of str to BroadbandBoundary
        Each track's broadband boundary (fitted over :data:`STUDY_BAND`).
    bands : mapping of str to (float, float)
        Each system's fit band (Hz).
    df : float
        Grid step (Hz) of the errors.

    Returns
    -------
    pandas.DataFrame
        Indexed by track; the system's DOFs and its max error (%) in its band and over
        :data:`STUDY_BAND`, the boundary's states and its max error (%) over :data:`STUDY_BAND`.
    """
    rows = {}
    full = _band_text(STUDY_BAND)
    for name, track in tracks.items():
        e = band_errors(track, {"system": systems[name]}, {"own": bands[name], "full": STUDY_BAND}, df).iloc[0]
        rows[name] = {"N = 5 system: DOFs": systems[name].matrices()[0].shape[0],
                      "N = 5 system: max error in its band (%)": e["own: max error (%)"],
                      f"N = 5 system: max error {full} (%)": e["full: max error (%)"],
                      "boundary: states": boundaries[name].state_space().n_states,
                      f"boundary: max error {full} (%)": 100 * boundaries[name].max_error}
    return pd.DataFrame.from_dict(rows, orient="index")


def band_errors(track: Track, models: Mapping[str, object], bands: Mapping[str, tuple[float, float]],
                df: float = 3.0) -> pd.DataFrame:
    """Median and maximum error of end models' alpha against the exact alpha, band by band.

    Parameters
    ----------
    track : Track
        The track; its exact (transfer-method) receptance is the reference.
    models : mapping of str to object
        End models by label; each has ``receptance(f)`` (f in Hz, shape ``(n, 2, 2)``), e.g. an
        :class:`~semitrack.EquivalentSystem` or a :class:`~semitrack.BroadbandBoundary`.
    bands : mapping of str to (float, float)
        Bands (Hz) by label; the errors are taken on each band's ``df`` grid.
    df : float
        Grid step (Hz).

    Returns
    -------
    pandas.DataFrame
        Indexed by model label; columns ``"<band>: median error (%)"`` and
        ``"<band>: max error (%)"`` per band (elements alpha11, alpha12, alpha22).
    """
    track = require_track(track)
    table = {}
    for band_label, band in bands.items():
        grid = error_band_grid(check_band(band), df)
        reference = semi_infinite_receptance(track, grid)
        for label, model in models.items():
            e = error_summary(model.receptance(grid), reference)
            table.setdefault(label, {})[f"{band_label}: median error (%)"] = 100 * e.median
            table[label][f"{band_label}: max error (%)"] = 100 * e.max
    return pd.DataFrame.from_dict(table, orient="index")


def error_curves(track: Track, models: Mapping[str, object], f: ArrayLike) -> pd.DataFrame:
    """The largest element error of each end model's alpha at each frequency.

    Parameters
    ----------
    track : Track
        The track (exact receptance as the reference).
    models : mapping of str to object
        End models by label, each with ``receptance(f)`` (Hz).
    f : array_like
        Frequencies (Hz).

    Returns
    -------
    pandas.DataFrame
        Indexed by frequency (Hz), one column per model: ``max_ij |alpha_ij - exact| / |exact|``
        over alpha11, alpha12, alpha22 (-).
    """
    f = np.atleast_1d(as_frequencies(f))
    reference = semi_infinite_receptance(require_track(track), f)
    out = {label: np.max(list(receptance_errors(model.receptance(f), reference).values()), axis=0)
           for label, model in models.items()}
    return pd.DataFrame(out, index=pd.Index(f, name="f (Hz)"))


def receptance_curves(track: Track, models: Mapping[str, object], f: ArrayLike) -> dict[str, np.ndarray]:
    """The exact alpha and each end model's alpha over ``f``, for a magnitude figure.

    Parameters
    ----------
    track : Track
        The track.
    models : mapping of str to object
        End models by label, each with ``receptance(f)`` (Hz).
    f : array_like
        Frequencies (Hz).

    Returns
    -------
    dict
        ``{"exact": alpha, label: alpha, ...}``, arrays of shape ``(n_f, 2, 2)`` (m/N, 1/N,
        rad/(N m)).
    """
    f = np.atleast_1d(as_frequencies(f))
    out = {EXACT_LABEL: semi_infinite_receptance(require_track(track), f)}
    out.update({label: model.receptance(f) for label, model in models.items()})
    return out


def limits_table(track: Track, boundary: BroadbandBoundary, f_track: float = 3e4,
                 f_model: float = 1e6) -> pd.DataFrame:
    """The two limits a boundary pins, the static stiffness K0 and the dashpot D, checked.

    ``K0`` is the exact ``Re K`` at 1 mHz and ``D = diag(sqrt(kappa A G rho A), sqrt(E I rho I))``
    (:func:`semitrack.boundary.fitting.track_end_limits`). The boundary's ``Re K`` at 1 mHz is
    compared with ``K0``; ``Re K / (i omega)`` of the boundary at ``f_model`` and of the exact
    track at ``f_track`` with the diagonal of ``D``.

    Parameters
    ----------
    track : Track
        The track the boundary was fitted to.
    boundary : BroadbandBoundary
        Its boundary.
    f_track, f_model : float
        High frequencies (Hz) at which the track and the boundary are compared with ``D``.

    Returns
    -------
    pandas.DataFrame
        Indexed by the limit and element (units in the name); columns ``value`` (SI),
        ``boundary / value`` and ``exact track / value`` (-; NaN for ``K0``, which is the
        track's own ``Re K`` at 1 mHz), ``ratios at`` (text).
    """
    K0, D = track_end_limits(require_track(track))
    f0 = 1e-3
    k_bnd = boundary.dynamic_stiffness([f0])[0].real
    z_bnd = (boundary.dynamic_stiffness([f_model])[0] / (2j * np.pi * f_model)).real
    k_track = np.linalg.inv(semi_infinite_receptance(track, [f_track])[0])
    z_track = (k_track / (2j * np.pi * f_track)).real
    units = {"alpha11": ("N/m", "N s/m"), "alpha12": ("N/rad", None), "alpha22": ("N m/rad", "N m s/rad")}
    rows = {}
    for name, (i, k) in ELEMENTS.items():
        rows[f"K0_{i + 1}{k + 1} ({units[name][0]})"] = (K0[i, k], k_bnd[i, k] / K0[i, k], np.nan, f"{f0 * 1e3:g} mHz")
    for name, (i, k) in ELEMENTS.items():
        if units[name][1] is not None:  # D is diagonal
            rows[f"D_{i + 1}{k + 1} ({units[name][1]})"] = (
                D[i, k], z_bnd[i, k] / D[i, k], z_track[i, k] / D[i, k],
                f"boundary {f_model / 1e3:g} kHz, track {f_track / 1e3:g} kHz")
    return pd.DataFrame.from_dict(rows, orient="index",
                                  columns=["value", "boundary / value", "exact track / value", "ratios at"])


def order_study(track: Track, orders: Iterable[int] = (12, 24, 36, 48), band: tuple[float, float] = STUDY_BAND,
                reuse: Iterable[BroadbandBoundary] = ()) -> pd.DataFrame:
    """The boundary's error against its number of poles.

    Parameters
    ----------
    track : Track
        The track.
    orders : iterable of int
        Numbers of poles (complex pairs counted twice) for :func:`semitrack.fit_boundary`.
    band : tuple of float
        Fit band (Hz).
    reuse : iterable of BroadbandBoundary
        Fits of this track and band already made (e.g. the automatic order's); an order that
        one of them tried on its way (``orders_tried``) is not fitted again (the fit is
        deterministic).

    Returns
    -------
    pandas.DataFrame
        One row per order: ``n_poles``, ``states``, ``median error (%)``, ``max error (%)``,
        ``proven passive``, ``enforcement rounds``, ``fit time (s)``.
    """
    # Every order a fit of this band tried (the automatic search tries several) is reused: the
    # fit at a given order is deterministic, so refitting it would only repeat the same work.
    known = {n: trial for b in reuse if tuple(b.band) == tuple(check_band(band))
             for n, trial in b.orders_tried.items()}
    rows = []
    for n in orders:
        trial = known.get(n)
        if trial is None:
            b = fit_boundary(track, band=band, n_poles=check_int_at_least("n_poles", n, 2))
            trial = b.orders_tried[b.n_poles]
        rows.append((n, 2 * n, 100 * trial.median, 100 * trial.max, trial.passive,
                     trial.enforcement_rounds, trial.elapsed))
    return pd.DataFrame(rows, columns=["n_poles", "states", "median error (%)", "max error (%)",
                                       "proven passive", "enforcement rounds", "fit time (s)"])


@dataclass(frozen=True)
class LossFactorBound:
    """The best Maxwell-element model of a spring with a constant loss factor, over a band.

    Attributes
    ----------
    eta : float
        The loss factor (-).
    error : float
        Smallest achievable maximum relative error ``|K_model / k - (1 + i eta)| / |1 + i eta|``
        over the band (-), within the 16-sided polygon approximation of the complex modulus.
    passive : bool
        Whether the elements were required to be passive (non-negative stiffnesses).
    min_loss_below_band : float
        Smallest ``Im K_model / k`` between 1 mHz and the band's lower end (-); negative means
        negative damping there (an active model).
    """

    eta: float
    error: float
    passive: bool
    min_loss_below_band: float


def _maxwell_rows(s: np.ndarray, a: np.ndarray, target: complex, n_directions: int):
    """Rows ``G k - t <= h`` of ``Re(e^{-i theta} (1 + phi k - target)) / |target| <= t``."""
    phi = s[:, None] / (s[:, None] + a[None, :])
    rot = np.exp(-2j * np.pi * np.arange(n_directions) / n_directions)
    G = (rot[:, None, None] * phi[None]).real.reshape(-1, a.size) / abs(target)
    h = np.repeat(-(rot * (1 - target)).real / abs(target), s.size)
    return G, h


def maxwell_loss_bound(eta: float, band: tuple[float, float] = STUDY_BAND, passive: bool = True,
                       coefficient_limit: float = 10.0, n_elements: int = 91, n_directions: int = 16,
                       n_freq: int = 200) -> LossFactorBound:
    """How closely a causal model with pinned static stiffness can follow a constant loss factor.

    A spring ``k (1 + i eta)`` with constant ``eta`` is not causal (its real and imaginary
    parts violate the Kramers-Kronig relations). Its causal stand-ins with the static stiffness
    pinned are ``k (1 + sum_m k_m s / (s + a_m))``: Maxwell elements (a spring ``k k_m`` in
    series with a dashpot, relaxation rate ``a_m``), passive when every ``k_m >= 0``. A linear
    programme finds the ``k_m`` (rates log-spaced from 1 mHz to 1 MHz) with the least maximum
    relative error over the band; the modulus of a complex error is approximated from below by
    a regular polygon of ``n_directions`` sides (``|z| >= max_j Re(z e^{-i theta_j})``, within a
    factor ``cos(pi / n_directions)``, 2 % for 16).

    Parameters
    ----------
    eta : float
        Loss factor (-), positive.
    band : tuple of float
        Band (Hz) of the fit.
    passive : bool
        Require ``k_m >= 0`` (passive); otherwise ``|k_m| <= coefficient_limit``.
    coefficient_limit : float
        Bound on the elements' relative stiffness ``|k_m|`` (-) of a non-passive model (keeps
        the programme bounded).
    n_elements, n_directions, n_freq : int
        Number of Maxwell elements, of polygon sides, and of log-spaced frequencies in the band.

    Returns
    -------
    LossFactorBound

    Examples
    --------
    >>> round(maxwell_loss_bound(0.1).error / 0.1, 2)
    0.87
    """
    eta = check_positive("eta", eta)
    lo, hi = check_band(band)
    s = 2j * np.pi * np.geomspace(lo, hi, check_int_at_least("n_freq", n_freq, 2))
    a = 2 * np.pi * np.geomspace(1e-3, 1e6, check_int_at_least("n_elements", n_elements, 1))
    G, h = _maxwell_rows(s, a, 1 + 1j * eta, check_int_at_least("n_directions", n_directions, 4))
    limit = check_positive("coefficient_limit", coefficient_limit)
    bounds = [(0.0, None) if passive else (-limit, limit)] * a.size + [(0.0, None)]
    cost = np.zeros(a.size + 1)
    cost[-1] = 1.0
    res = linprog(cost, A_ub=np.hstack([G, -np.ones((G.shape[0], 1))]), b_ub=h, bounds=bounds, method="highs")
    if res.status != 0:
        raise RuntimeError(f"maxwell_loss_bound: the linear programme failed ({res.message})")
    s_below = 2j * np.pi * np.geomspace(1e-3, lo, 200)
    loss = (s_below[:, None] / (s_below[:, None] + a) @ res.x[:-1]).imag
    return LossFactorBound(eta=eta, error=float(res.x[-1]), passive=passive, min_loss_below_band=float(loss.min()))


def causality_table(loss_factors: Mapping[str, float], band: tuple[float, float] = STUDY_BAND,
                    coefficient_limit: float = 10.0) -> pd.DataFrame:
    """:func:`maxwell_loss_bound` for several loss factors, passive and not.

    Parameters
    ----------
    loss_factors : mapping of str to float
        Loss factors (-) by label, e.g. ``{"rail pad": 0.1, "ballast": 0.3}``.
    band : tuple of float
        Band (Hz).
    coefficient_limit : float
        ``|k_m|`` bound (-) of the non-passive models.

    Returns
    -------
    pandas.DataFrame
        Indexed by label; columns ``eta``, ``passive: max error (%)``, ``passive: error / eta``,
        ``active allowed: max error (%)`` and ``active allowed: min Im K / k below the band``.
    """
    rows = {}
    for label, eta in loss_factors.items():
        p = maxwell_loss_bound(eta, band)
        q = maxwell_loss_bound(eta, band, passive=False, coefficient_limit=coefficient_limit)
        rows[label] = (eta, 100 * p.error, p.error / eta, 100 * q.error, q.min_loss_below_band)
    return pd.DataFrame.from_dict(rows, orient="index", columns=[
        "eta", "passive: max error (%)", "passive: error / eta", "active allowed: max error (%)",
        "active allowed: min Im K / k below the band"])


def passivity_margin(boundary: BroadbandBoundary, f: ArrayLike) -> np.ndarray:
    """Smallest eigenvalue of the scaled damping ``D^-1/2 Re Z(i omega) D^-1/2`` at ``f``.

    ``Z = K / s - K0 / s`` is the boundary's impedance without its spring (force per end
    velocity); the end absorbs energy at a frequency exactly when this eigenvalue is >= 0. The
    scaling makes it dimensionless and 1 at high frequency. Sampling shows the margin; the
    proof that it stays positive between the samples is the Hamiltonian test
    (:meth:`semitrack.BroadbandBoundary.is_passive`).

    Parameters
    ----------
    boundary : BroadbandBoundary
        The boundary.
    f : array_like
        Frequencies (Hz), any range.

    Returns
    -------
    ndarray
        The smallest eigenvalue at each frequency (-).
    """
    model = boundary.rational
    w, v = np.linalg.eigh(model.D)
    S = v @ np.diag(w ** -0.5) @ v.T
    Z = model.impedance(2j * np.pi * np.atleast_1d(as_frequencies(f)))
    H = S @ (0.5 * (Z + np.conj(np.swapaxes(Z, 1, 2)))).real @ S
    return np.linalg.eigvalsh(H)[:, 0]


def compared_boundary_ends(boundary: BroadbandBoundary, system: EquivalentSystem | None = None) -> dict:
    """The kinds of end of the chapter's 10-bay models, under the labels its figures style.

    Parameters
    ----------
    boundary : BroadbandBoundary
        The broadband boundary of the track.
    system : EquivalentSystem, optional
        An N = 5 equivalent system of the track (left out when None).

    Returns
    -------
    dict
        ``{"pinned", ["N = 5 system",] "broadband boundary", "exact end stiffness"}`` to the ends
        (:mod:`semitrack.fe.ends`) for :func:`semitrack.fe.truncation.truncated_w1`.
    """
    ends = [PINNED]
    if system is not None:
        ends.append(EquivalentEnd(label="N = 5 system", equivalent=system))
    ends += [BoundaryEnd(label="broadband boundary", boundary=boundary), replace(EXACT, label="exact end stiffness")]
    return {end.label: end for end in ends}


def w1_error_table(curves: Mapping[tuple, pd.DataFrame], bands: Mapping[tuple, tuple[float, float]],
                   full_band: tuple[float, float] = STUDY_BAND) -> pd.DataFrame:
    """Median and maximum error of truncated tracks' w1 over the full band and over a sub-band.

    Parameters
    ----------
    curves : mapping of tuple to pandas.DataFrame
        ``{(track, damping): table of semitrack.fe.truncation.truncated_w1}`` (indexed by
        frequency in Hz; column ``"infinite track (exact)"`` and one per kind of end, m/N).
    bands : mapping of tuple to (float, float)
        The sub-band (Hz) of each key, e.g. the N = 5 systems' fit band.
    full_band : tuple of float
        The full band (Hz), for the column names.

    Returns
    -------
    pandas.DataFrame
        Indexed by (track, damping, ends); columns ``"<full band>: median error (%)"``,
        ``"<full band>: max error (%)"``, ``"N = 5 band"`` (text) and its median and max (%).
    """
    rows = {}
    full = _band_text(full_band)
    for key, table in curves.items():
        f = table.index.to_numpy()
        lo, hi = bands[key]
        inside = (f >= lo) & (f <= hi)
        exact = table["infinite track (exact)"].to_numpy()
        for label in table.columns.drop("infinite track (exact)"):
            e = 100 * np.abs(table[label].to_numpy() - exact) / np.abs(exact)
            rows[(*key, label)] = (np.median(e), e.max(), _band_text((lo, hi)), np.median(e[inside]), e[inside].max())
    table = pd.DataFrame.from_dict(rows, orient="index", columns=[
        f"{full}: median error (%)", f"{full}: max error (%)", "N = 5 band", "N = 5 band: median error (%)",
        "N = 5 band: max error (%)"])
    table.index = pd.MultiIndex.from_tuples(table.index, names=["track", "damping", "ends"])
    return table


def pulse_study(track: Track, boundary: BroadbandBoundary, n_bays: int = 10, reference_bays: int = 100,
                f_max: float = 6000.0, dt: float = 1e-5, duration: float = 0.03) -> dict:
    """A broadband Hann pulse on 10-bay models with pinned and broadband-boundary ends.

    The pulse lasts ``2 / f_max`` at the centre; the rail displacement is recorded at the centre
    and three bays away, and compared with a long pinned reference (8 elements per bay for all).

    Parameters
    ----------
    track : Track
        The track, with viscous damping (the time-domain rail is viscously damped).
    boundary : BroadbandBoundary
        The boundary fitted to this track.
    n_bays, reference_bays : int
        Bays on each side of the truncated models and of the reference.
    f_max : float
        First zero of the pulse's spectrum (Hz).
    dt, duration : float
        Time step and the run's length (s).

    Returns
    -------
    dict
        The result of :func:`semitrack.fe.truncation.truncation_errors`: ``"reference"``,
        ``"pinned"``, ``"boundary"`` (TimeHistory, ``t`` in s, ``u`` in m per N) and ``"errors"``
        (relative L2 errors per position, -).
    """
    return truncation_errors(track, None, n_bays=n_bays, reference_bays=reference_bays,
                             ends=(PINNED.name, BoundaryEnd.name), boundary=boundary, elements_per_bay=8,
                             x=(0.0, 3 * track.spacing), f_max=f_max, dt=dt, duration=duration)


def pulse_error_table(results: Mapping[str, dict]) -> pd.DataFrame:
    """Relative L2 errors of the pulse responses, pinned against broadband-boundary ends.

    Parameters
    ----------
    results : mapping of str to dict
        ``{track: result of pulse_study}``.

    Returns
    -------
    pandas.DataFrame
        Indexed by (track, recorded displacement); columns ``pinned ends: L2 error (%)`` and
        ``boundary ends: L2 error (%)``.
    """
    rows = {}
    for name, res in results.items():
        for j, label in enumerate(res["reference"].labels):
            rows[(name, label)] = (100 * res["errors"][PINNED.name][j], 100 * res["errors"][BoundaryEnd.name][j])
    table = pd.DataFrame.from_dict(rows, orient="index",
                                   columns=["pinned ends: L2 error (%)", "boundary ends: L2 error (%)"])
    table.index = pd.MultiIndex.from_tuples(table.index, names=["track", "recorded"])
    return table


def mck_summary(boundaries: Mapping[str, BroadbandBoundary], f: ArrayLike | None = None) -> pd.DataFrame:
    """Each broadband end as M, C, K (:meth:`BroadbandBoundary.matrix_system`): size, time, exactness, definiteness.

    Parameters
    ----------
    boundaries : mapping of str to BroadbandBoundary
        Label to boundary.
    f : array_like, optional
        Frequencies of the comparison with the state space (Hz); default 1 mHz to 1 MHz, 400 points.

    Returns
    -------
    pandas.DataFrame
        One row per boundary: first-order states, internal DOFs, conversion time (s), the largest
        element error of the M, C, K receptance against the state space's, and the smallest
        eigenvalue of M, C and K relative to each one's largest.
    """
    f = np.geomspace(1e-3, 1e6, 400) if f is None else as_frequencies(f)
    rows = {}
    for label, bnd in boundaries.items():
        start = time.perf_counter()
        mck = bnd.matrix_system()
        wall = time.perf_counter() - start
        eig = min(np.linalg.eigvalsh(X)[0] / np.max(np.abs(np.linalg.eigvalsh(X))) for X in mck.matrices())
        rows[label] = {"states": bnd.state_space().A.shape[0], "internal DOFs": mck.n_internal,
                       "conversion (s)": wall, "largest error against the state space": float(
                           np.max(np.abs(mck.receptance(f) / bnd.receptance(f) - 1))),
                       "smallest relative eigenvalue of M, C, K": float(eig)}
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("broadband end")


def mck_pulse_study(track: Track, boundary: BroadbandBoundary, system: EquivalentSystem, n_bays: int = 10,
                    reference_bays: int = 100, **kwargs) -> dict:
    """The same broadband pulse as :func:`pulse_study` on 10-bay models closed by the paper's system, the
    broadband end as M, C, K, and the broadband end as its state space.

    Parameters
    ----------
    track : Track
        The track (viscous damping).
    boundary : BroadbandBoundary
        Its broadband end.
    system : EquivalentSystem
        The paper's equivalent system for the track (Table 4 or 7).
    n_bays, reference_bays : int
        Bays of the truncated models and of the long pinned reference.
    **kwargs
        Passed on to :func:`semitrack.fe.truncation.truncation_errors` (``f_max``, ``dt``, ``duration``).

    Returns
    -------
    dict
        The result of :func:`~semitrack.fe.truncation.truncation_errors`, keyed by the ends' labels,
        and ``"M, C, K against the state space"``: the relative L2 difference of the two broadband
        models' responses per position.
    """
    labels = ("the paper's system", "broadband end as M, C, K", "broadband end as state space")
    ends = (EquivalentEnd(label=labels[0], equivalent=system),
            EquivalentEnd(label=labels[1], equivalent=boundary.matrix_system()),
            BoundaryEnd(label=labels[2], boundary=boundary))
    settings = dict(x=(0.0, 3 * track.spacing), f_max=6000.0, dt=1e-5, duration=0.03)
    settings.update(kwargs)
    out = truncation_errors(track, None, n_bays=n_bays, reference_bays=reference_bays, ends=ends,
                            elements_per_bay=8, **settings)
    out["M, C, K against the state space"] = relative_l2_error(out[labels[1]].u, out[labels[2]].u)
    return out
