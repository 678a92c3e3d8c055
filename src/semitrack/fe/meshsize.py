"""A mesh that follows the frequencies asked: the elements per bay whose own error stays under a tolerance.

The error of the rail's mesh is largest at the sharp pinned-pinned peaks, where a small shift of
the FE resonance is a large error of the response: measured on the paper's tracks against the
exact infinite track, 12 elements per bay are 6-29 % off there below 3 kHz, 48 are 0.35-1.9 %
off. It falls as ``1 / n^2`` with the elements per bay n (measured: 4.15 % at 32, 1.04 % at 64
on the ballasted track). So the error is *measured* once per track, not guessed from a rule of
thumb that would hold for one track only:

1. the periodic track is modelled with :data:`PROBE_ELEMENTS` elements per bay, three bays each
   side of a mid-span, closed by the exact ends (nothing truncated: the mesh is the only
   approximation);
2. the receptance w/F at a mid-span and at a support is compared with
   :class:`semitrack.InfiniteTrack` (exact, no mesh) on a :data:`PROBE_STEP` grid; the error curve
   is its running maximum over frequency;
3. n elements per bay have the error ``(PROBE_ELEMENTS / n)^2`` times that curve; the default
   mesh is the fewest (even, at least :data:`MIN_ELEMENTS`) that keep it under the tolerance up
   to the highest frequency of interest, with a :data:`SAFETY` margin in n.

The probe is measured by :func:`semitrack.fe.models.mesh_probe` (it needs the FE model; about
a second per track and frequency range, cached for the process); this module holds the law. Changed
supports, a transition's second track (probed too: the finer of the two meshes is used) and
joints keep the periodic track's estimate: their local errors are of the same order.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ..base.checks import check_in_range, check_positive

__all__ = ["PROBE_ELEMENTS", "PROBE_STEP", "MIN_ELEMENTS", "SAFETY", "MESH_TOLERANCE", "MeshProbe", "probe_grid",
           "elements_for", "valid_frequency", "MAX_MESH_FREQUENCY"]

#: Elements per bay of the probe model (the error measured there scales as 1/n^2 to other n).
PROBE_ELEMENTS = 24
#: Frequency step of the probe (Hz): a few points across the narrowest pinned-pinned peak.
PROBE_STEP = 2.0
#: The coarsest default mesh: below it the 1/n^2 law no longer holds.
MIN_ELEMENTS = 8
#: Margin on the elements per bay (1.1: the error 0.83 of the tolerance by the law).
SAFETY = 1.1
#: The default tolerance of the mesh's own error (max relative error of w/F).
MESH_TOLERANCE = 0.01
#: The highest ``f_max`` a default mesh is sized for (Hz): far above the Timoshenko rail's range of
#: validity (a few kHz), and a probe grid of 10 000 frequencies.
MAX_MESH_FREQUENCY = 20_000.0


def probe_grid(f_max: float) -> np.ndarray:
    """The probe's frequencies (Hz) up to ``f_max`` rounded up to a whole 500 Hz (so that probes are shared).

    Parameters
    ----------
    f_max : float
        Highest frequency of interest (Hz).

    Returns
    -------
    ndarray
        Every :data:`PROBE_STEP` Hz from :data:`PROBE_STEP`.
    """
    f_max = check_in_range("f_max", check_positive("f_max", f_max), (1.0, MAX_MESH_FREQUENCY),
                           "Hz, the range a default mesh is sized for; give elements_per_bay for more")
    top = 500.0 * np.ceil(f_max / 500.0)
    return np.arange(PROBE_STEP, top + PROBE_STEP / 2, PROBE_STEP)


@dataclass(frozen=True)
class MeshProbe:
    """The mesh error of one track measured at :data:`PROBE_ELEMENTS` elements per bay.

    Attributes
    ----------
    f : ndarray
        Frequencies (Hz), :func:`probe_grid`.
    error : ndarray
        The running maximum over frequency of the relative error of w/F (-).
    """

    f: np.ndarray
    error: np.ndarray

    def error_at(self, elements_per_bay: int, f_max: float) -> float:
        """The largest error of a mesh of ``elements_per_bay`` up to ``f_max`` (Hz), by the 1/n^2 law.

        Parameters
        ----------
        elements_per_bay : int
            Elements per bay.
        f_max : float
            Highest frequency (Hz), within the probe's.

        Returns
        -------
        float
        """
        i = max(int(np.searchsorted(self.f, f_max, side="right")) - 1, 0)
        return float(self.error[i] * (PROBE_ELEMENTS / elements_per_bay) ** 2)


def elements_for(probes: Iterable[MeshProbe], f_max: float, tol: float = MESH_TOLERANCE) -> int:
    """The default elements per bay: the fewest (even) whose own error stays under ``tol`` up to ``f_max``.

    Parameters
    ----------
    probes : iterable of MeshProbe
        The probes of the model's tracks (one, or the two of a transition: the finer mesh wins).
    f_max : float
        Highest frequency of interest (Hz).
    tol : float
        Tolerance of the largest relative error of w/F (-).

    Returns
    -------
    int
        Even, at least :data:`MIN_ELEMENTS`.

    Examples
    --------
    >>> f = probe_grid(1000.0)
    >>> elements_for([MeshProbe(f, np.full(f.size, 0.04))], 1000.0)  # 4 % at 24: 48 (1 %) x 1.1
    54
    """
    tol = check_positive("tol", tol)
    need = max(SAFETY * PROBE_ELEMENTS * np.sqrt(p.error_at(PROBE_ELEMENTS, f_max) / tol) for p in probes)
    return int(max(MIN_ELEMENTS, 2 * np.ceil(need / 2)))


def valid_frequency(probes: Iterable[MeshProbe], elements_per_bay: int, tol: float = MESH_TOLERANCE) -> float:
    """The highest frequency up to which a mesh's own error stays under ``tol``, within the probes' range.

    Parameters
    ----------
    probes : iterable of MeshProbe
        The probes of the model's tracks.
    elements_per_bay : int
        Elements per bay of the mesh.
    tol : float
        Tolerance of the largest relative error of w/F (-).

    Returns
    -------
    float
        Hz; the probes' highest frequency when their whole range is within ``tol``.
    """
    out = np.inf
    for p in probes:
        bad = np.flatnonzero(p.error * (PROBE_ELEMENTS / elements_per_bay) ** 2 > tol)
        out = min(out, float(p.f[-1]) if not bad.size else float(p.f[bad[0] - 1]) if bad[0] else 0.0)
    return out
