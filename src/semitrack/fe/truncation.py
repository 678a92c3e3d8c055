"""How long must a truncated track be? Its error against the infinite track, by kind of end.

Frequency domain
    For each end condition of :class:`semitrack.fe.models.TruncatedTrack` and each number of
    bays, the vertical receptance at the central cross-section is compared with the exact
    infinite-track w1 (:func:`semitrack.central_response`); the measures are the median and the
    maximum relative error over a band (:func:`truncation_study`, :func:`bays_needed`,
    :func:`errors_at`, :func:`truncated_w1`). One band solve per frequency and length serves
    every kind of end (:func:`central_w1_by_ends`).

Time domain
    The same truncated models and a long reference track run the same excitation (a Hann pulse
    or a moving load, :mod:`semitrack.fe.timedomain`); the measure is the relative L2 error of
    the recorded displacements over the window (:func:`truncation_errors`,
    :func:`time_domain_study`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Literal

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from ..base.checks import as_frequencies, check_choice
from ..base.deprecation import renamed_keywords
from ..base.errors import InputTypeError
from ..boundary.fitting import BroadbandBoundary
from ..equivalent.assembly import scaled_solve
from ..equivalent.systems import EquivalentSystem
from ..methods.receptance import central_response
from ..model.tracks import Track
from .ends import EXACT, FREE, PINNED, End, EndName, EquivalentEnd, end_kinds, make_end
from .mesh import KINDS, SIDES, rail_dof
from .models import TruncatedTrack
from .timedomain import moving_load_response, pulse_response, relative_l2_error

__all__ = [
    "compared_ends",
    "truncation_study",
    "bays_needed",
    "errors_at",
    "truncated_w1",
    "central_w1_by_ends",
    "truncation_errors",
    "TimeDomainStudy",
    "time_domain_study",
]

#: ``{label: end}``: the end conditions of a study, by the label of its rows; an end is an
#: :class:`~semitrack.fe.ends.End` or a pair ``(name, system)`` for :func:`~semitrack.fe.ends.make_end`.
EndsSpec = Mapping[str, End | tuple[EndName, EquivalentSystem | BroadbandBoundary | None]]


def _as_end(spec: End | tuple) -> End:
    if isinstance(spec, End):
        return spec
    try:
        kind, system = spec
    except (TypeError, ValueError):
        raise InputTypeError(f"an end of a study must be an End or a pair (name, system), got {spec!r}") from None
    return make_end(kind, system)


def compared_ends(paper_system: EquivalentSystem, our_system: EquivalentSystem) -> dict:
    """The five kinds of end the book compares, under the labels its figures style.

    Parameters
    ----------
    paper_system : EquivalentSystem
        The paper's system for the track (Table 4 or Table 7).
    our_system : EquivalentSystem
        A system fitted to the exact receptance.

    Returns
    -------
    dict
        ``{"pinned", "free", "paper system", "our system", "exact end stiffness"}`` to the ends
        (:mod:`semitrack.fe.ends`) for :func:`truncation_study`.

    Examples
    --------
    >>> import semitrack as st
    >>> list(compared_ends(st.paper_table4(), st.paper_table4()))
    ['pinned', 'free', 'paper system', 'our system', 'exact end stiffness']
    """
    paper = EquivalentEnd(label="paper system", equivalent=paper_system)
    ours = EquivalentEnd(label="our system", equivalent=our_system)
    exact = replace(EXACT, label="exact end stiffness")
    return {end.label: end for end in (PINNED, FREE, paper, ours, exact)}


def truncation_study(track: Track, f: ArrayLike, n_bays: Sequence[int] = (1, 2, 5, 10, 20, 40, 80),
                     ends: EndsSpec | None = None, elements_per_bay: int = 12) -> pd.DataFrame:
    """Median and maximum relative error of w1 of truncated tracks over the frequencies ``f``.

    Parameters
    ----------
    track : Track
        The track.
    f : array_like
        Frequencies (Hz) over which the errors are taken.
    n_bays : sequence of int
        Bays on each side of the centre.
    ends : dict, optional
        Label -> end (an :class:`~semitrack.fe.ends.End`, or ``(name, system)``) for
        :class:`TruncatedTrack`, e.g. ``{"pinned": ("pinned", None), "paper system":
        ("equivalent", paper_table4())}`` or :func:`compared_ends`. Default: pinned, free and
        exact ends.
    elements_per_bay : int
        FE mesh (12 gives about 0.5 % discretisation error up to 3 kHz).

    Returns
    -------
    pandas.DataFrame
        Columns ``ends, n_bays, median error, max error`` (fractions).

    Examples
    --------
    >>> import semitrack as st
    >>> study = truncation_study(st.slab_track(), [50.0, 100.0], n_bays=(1, 2), elements_per_bay=4)
    >>> study.shape, list(study["ends"].unique())
    ((6, 4), ['pinned', 'free', 'exact'])
    """
    f = np.atleast_1d(as_frequencies(f))
    ends = ends or {end.label: end for end in (PINNED, FREE, EXACT)}
    w1 = central_response(track, f).w1
    by_bays = {n: central_w1_by_ends(track, f, n, ends, elements_per_bay) for n in n_bays}
    rows = []
    for label in ends:
        for n in n_bays:
            err = np.abs(by_bays[n][label] - w1) / np.abs(w1)
            rows.append((label, n, float(np.median(err)), float(err.max())))
    return pd.DataFrame(rows, columns=["ends", "n_bays", "median error", "max error"])


def central_w1_by_ends(track: Track, f: ArrayLike, n_bays: int, ends: EndsSpec,
                       elements_per_bay: int = 12) -> dict[str, np.ndarray]:
    """w1 at the centre of ``TruncatedTrack(track, n_bays, kind, system)`` for every entry of ``ends``.

    One band solve per frequency serves every kind of end: the free-ended model is solved for
    unit loads at its centre and at its two end nodes (w and psi each), which condenses it
    exactly to the dynamic stiffness ``D = F^-1`` of those six DOFs (``F`` their flexibility;
    the chain carries no other load). Each kind of end then only changes a small system: pinned
    ends remove the end ``w``, exact and boundary ends add their 2x2 end stiffness (mirrored at
    the left end), an equivalent system adds its ``K + i omega C - omega^2 M`` with its internal
    DOFs (mirrored rotation at the left end), as :class:`TruncatedTrack` assembles them. The same
    w1 as each model's own solve to ~1e-10 (tested), at one factorisation instead of one per end.

    Parameters
    ----------
    track : Track
        The track.
    f : array_like
        Frequencies (Hz), 1-D.
    n_bays : int
        Bays on each side of the centre (>= 1; with 0 each model is solved on its own).
    ends : dict
        Label -> end as in :func:`truncation_study`.
    elements_per_bay : int
        FE mesh.

    Returns
    -------
    dict
        Label -> w1 (m/N), complex, one value per frequency.
    """
    f = np.atleast_1d(as_frequencies(f))
    ends = {label: _as_end(spec) for label, spec in ends.items()}
    if n_bays == 0:
        return {label: TruncatedTrack(track, 0, end, elements_per_bay=elements_per_bay).central_receptance(f)[:, 0, 0]
                for label, end in ends.items()}
    free = TruncatedTrack(track, n_bays, FREE, elements_per_bay=elements_per_bay)
    keys = [free.dof(0.0, "w"), free.dof(0.0, "psi")]
    for side in SIDES:  # left end (w, psi), then right end
        node = free.mesh.end_node(side)
        keys += [int(free.dofs.index[rail_dof(node, kind)]) for kind in KINDS]
    rhs = np.zeros((free.n_dof, len(keys)))
    rhs[keys, np.arange(len(keys))] = 1.0
    D = _scaled_inverse(free.solve(f, rhs)[:, keys, :])  # (n_f, 6, 6): the chain condensed
    omega = 2 * np.pi * f
    return {label: _with_ends(track, D, omega, end) for label, end in ends.items()}


def _scaled_inverse(F: np.ndarray) -> np.ndarray:
    """``F^-1`` per frequency, with symmetric diagonal scaling (w and psi differ by decades)."""
    d = np.sqrt(np.abs(np.diagonal(F, axis1=1, axis2=2)))
    s = 1.0 / np.where(d > 0, d, 1.0)
    return s[:, :, None] * np.linalg.inv(s[:, :, None] * F * s[:, None, :]) * s[:, None, :]


# Rows of the condensed system: centre (w, psi), left end (w, psi), right end (w, psi).
_END_ROWS = {"left": slice(2, 4), "right": slice(4, 6)}


def _with_ends(track: Track, D: np.ndarray, omega: np.ndarray, end: End) -> np.ndarray:
    """w1 at the centre of the condensed chain ``D`` closed by ``end`` at both sides.

    Each end adds its dynamic stiffness on its DOFs (the rail's ``(w, psi)`` at the end, then
    its internal DOFs, appended), as :class:`TruncatedTrack` assembles it; a pinned end removes
    its ``w``.
    """
    n0, m = D.shape[1], end.internal_dofs
    Z = np.zeros((D.shape[0], n0 + 2 * m, n0 + 2 * m), dtype=complex)
    Z[:, :n0, :n0] = D
    for k, side in enumerate(SIDES):
        rows = _END_ROWS[side]
        idx = np.concatenate((np.arange(rows.start, rows.stop), n0 + k * m + np.arange(m)))
        Z[:, idx[:, None], idx[None, :]] += end.dynamic_stiffness(track, omega, side)
    keep = np.ones(Z.shape[1], dtype=bool)
    if end.removes_w:
        keep[[_END_ROWS["left"].start, _END_ROWS["right"].start]] = False
    Z = Z[:, keep][:, :, keep]
    load = np.zeros((Z.shape[1], 1))
    load[0, 0] = 1.0
    return scaled_solve(Z, load)[:, 0, 0]


@renamed_keywords({"median": "median_error", "maximum": "max_error"})
def bays_needed(study: pd.DataFrame, median_error: float = 0.05, max_error: float = 0.10) -> pd.Series:
    """Fewest bays (each side) in ``study`` meeting both error targets, per end condition.

    Parameters
    ----------
    study : pandas.DataFrame
        A table of :func:`truncation_study`.
    median_error, max_error : float
        Targets for the median and the maximum relative error of w1 (fractions; ``median=`` and
        ``maximum=`` until 0.3).

    Returns
    -------
    pandas.Series
        Bays per label of ``study["ends"]``, in the study's order; NaN where no length in the
        study meets the targets.
    """
    ok = study[(study["median error"] <= median_error) & (study["max error"] <= max_error)]
    needed = ok.groupby("ends", sort=False)["n_bays"].min()
    return needed.reindex(study["ends"].unique())


def errors_at(studies: Mapping[str, pd.DataFrame], n_bays: int) -> pd.DataFrame:
    """The errors of several studies at one length, side by side, in percent.

    Parameters
    ----------
    studies : dict
        ``{track name: table of truncation_study}``.
    n_bays : int
        The number of bays on each side to read off (must be in every study).

    Returns
    -------
    pandas.DataFrame
        Indexed by the ends' labels; columns ``"<track>: median error (%)"`` and
        ``"<track>: max error (%)"`` per study.
    """
    table = pd.concat({name: study[study.n_bays == n_bays].set_index("ends")[["median error", "max error"]] * 100
                       for name, study in studies.items()}, axis=1)
    table.columns = [f"{t}: {c} (%)" for t, c in table.columns]
    return table


def truncated_w1(track: Track, f: ArrayLike, n_bays: int, ends: EndsSpec,
                 elements_per_bay: int = 12) -> pd.DataFrame:
    """w1 of the infinite track and of truncated tracks of one length, over ``f``.

    Parameters
    ----------
    track : Track
        The track.
    f : array_like
        Frequencies (Hz), 1-D.
    n_bays : int
        Bays on each side of the centre of every truncated model.
    ends : dict
        Label -> end as in :func:`truncation_study`.
    elements_per_bay : int
        FE mesh.

    Returns
    -------
    pandas.DataFrame of complex
        Indexed by frequency (Hz); a column ``"infinite track (exact)"`` and one per label of
        ``ends`` (m/N).
    """
    f = np.atleast_1d(as_frequencies(f))
    out = {"infinite track (exact)": central_response(track, f).w1}
    out.update(central_w1_by_ends(track, f, n_bays, ends, elements_per_bay))
    return pd.DataFrame(out, index=pd.Index(f, name="f (Hz)"))


# ------------------------------------------------------------------------------------------------
# Time domain
# ------------------------------------------------------------------------------------------------
def truncation_errors(track: Track, system: EquivalentSystem | None, n_bays: int = 10, reference_bays: int = 200,
                      excitation: Literal["pulse", "moving"] = "pulse", ends: Sequence[EndName | End] | None = None,
                      elements_per_bay: int = 8, boundary: BroadbandBoundary | None = None, **kwargs) -> dict:
    """Time-domain error of truncated models against a long reference track.

    Builds ``TruncatedTrack(track, n_bays, ends=e, system=...)`` for each end condition in
    ``ends`` and a pinned reference ``TruncatedTrack(track, reference_bays)`` (long enough that
    no end reflection returns within the window: check by doubling it), all with the same mesh,
    runs the same excitation on each and compares the outputs.

    Parameters
    ----------
    track : Track
        The track.
    system : EquivalentSystem or None
        The equivalent system of ``"equivalent"`` ends.
    n_bays, reference_bays : int
        Bays on each side of the centre of the truncated models and of the reference.
    excitation : {"pulse", "moving"}
        :func:`~semitrack.fe.timedomain.pulse_response` or
        :func:`~semitrack.fe.timedomain.moving_load_response`.
    ends : sequence of str or End, optional
        End conditions of the truncated models ("pinned", "free", "equivalent", "boundary", or
        :mod:`semitrack.fe.ends` objects); default pinned and equivalent.
    elements_per_bay : int
        Mesh of all models.
    boundary : BroadbandBoundary, optional
        The broadband boundary of ``"boundary"`` ends (fit it to the track with
        ``damping="viscous"``: the time-domain rail is viscously damped).
    **kwargs
        Passed on to the excitation's function (positions, times, load...).

    Returns
    -------
    dict
        ``{"reference": TimeHistory, e: TimeHistory, ..., "errors": {e: ndarray per output}}``
        (errors as fractions).
    """
    check_choice("excitation", excitation, ("pulse", "moving"))
    run = pulse_response if excitation == "pulse" else moving_load_response
    ends = (PINNED.name, EquivalentEnd.name) if ends is None else ends
    ref_model = TruncatedTrack(track, reference_bays, PINNED, elements_per_bay=elements_per_bay)
    out = {"reference": run(ref_model, **kwargs), "errors": {}}
    for spec in ends:
        end, key = (spec, spec.label) if isinstance(spec, End) else (_named_end(spec, system, boundary), spec)
        out[key] = run(TruncatedTrack(track, n_bays, end, elements_per_bay=elements_per_bay), **kwargs)
        out["errors"][key] = relative_l2_error(out[key].u, out["reference"].u)
    return out


def _named_end(name: str, system, boundary) -> End:
    """The end ``name`` with whichever of ``system`` and ``boundary`` its kind takes."""
    (kind,) = end_kinds(name)
    match = [s for s in (system, boundary) if kind.system_type is not None and isinstance(s, kind.system_type)]
    return make_end(name, match[0] if match else (system if kind.system_type is not None else None))


@dataclass(frozen=True)
class TimeDomainStudy:
    """Pinned and equivalent ends of one length against a long reference, for a pulse and a moving load.

    Attributes
    ----------
    pulse : dict
        :func:`truncation_errors` of a Hann pulse at the centre, recorded at the centre and
        three bays away.
    moving : dict
        :func:`truncation_errors` of a load moving at 300 km/h across the middle of the model.
    errors : pandas.DataFrame
        Columns ``track, case, pinned ends: L2 error (%), equivalent ends: L2 error (%)``, one
        row per recorded displacement.
    """

    pulse: dict
    moving: dict
    errors: pd.DataFrame


@renamed_keywords({"t_end": "duration"})
def time_domain_study(track: Track, system: EquivalentSystem, n_bays: int = 10, reference_bays: int = 100,
                      duration: float = 0.03, moving_bays: int = 4) -> TimeDomainStudy:
    """Truncated models with pinned and equivalent ends in the time domain (the book's two cases).

    Parameters
    ----------
    track : Track
        The track.
    system : EquivalentSystem
        The system of the equivalent ends.
    n_bays, reference_bays : int
        Bays on each side of the truncated models and of the pinned reference (8 elements per bay).
    duration : float
        The pulse run's length (s).
    moving_bays : int
        The load moves from ``-moving_bays d`` to ``moving_bays d``.

    Returns
    -------
    TimeDomainStudy
    """
    d = track.spacing
    common = dict(n_bays=n_bays, reference_bays=reference_bays)
    pulse = truncation_errors(track, system, excitation="pulse", x=(0.0, 3 * d), duration=duration, **common)
    moving = truncation_errors(track, system, excitation="moving", x_start=-moving_bays * d, x_end=moving_bays * d,
                               **common)
    cases = (("pulse, x = 0", pulse, 0), ("pulse, 3 bays away", pulse, 1), ("moving load, under the load", moving, 0))
    rows = [(track.name, case, 100 * res["errors"][PINNED.name][column],
             100 * res["errors"][EquivalentEnd.name][column]) for case, res, column in cases]
    errors = pd.DataFrame(rows, columns=["track", "case", "pinned ends: L2 error (%)", "equivalent ends: L2 error (%)"])
    return TimeDomainStudy(pulse=pulse, moving=moving, errors=errors)
