"""Export and import of a broadband boundary: JSON (exact round trip) and MATLAB .mat.

Both formats carry the full model (poles, coefficients, ``K0``, ``D``), its real state space
(``A, B, C, D, K0``: what a user's own time-domain code needs), the fit band, the median and
maximum errors, the passivity-enforcement rounds, and the units (the per-element errors, the
orders tried and the fit time are not kept). Loading rebuilds the model from poles and
coefficients and checks that the stored state space agrees with it, so a hand-edited or
mismatched file is refused rather than trusted.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import scipy.io

from ..base.errors import InputError, InputTypeError
from ..base.files import atomic_write
from ..equivalent.metrics import ErrorSummary
from .fitting import BroadbandBoundary
from .passivity import passivity_report
from .rational import RationalEndStiffness

__all__ = ["boundary_to_dict", "boundary_from_dict", "save_boundary", "load_boundary"]

FORMAT = "semitrack-broadband-boundary"
VERSION = 1
UNITS = {
    "poles": "rad/s (one member, Im > 0, per complex pair)",
    "coefficients": "columns (11, 12, 22) of the symmetric 2x2 coefficient of each real basis function",
    "K0": "N/m, N/rad (= N m/m), N m/rad",
    "D": "N s/m, N m s/rad",
    "state_space": "(Q, M) = K0 u + D du/dt + C x, dx/dt = A x + B du/dt; u = (w, psi) in m, rad",
    "frequency": "Hz",
}


def _check_boundary(boundary) -> BroadbandBoundary:
    if not isinstance(boundary, BroadbandBoundary):
        raise InputTypeError(f"boundary must be a BroadbandBoundary (from fit_boundary), got {type(boundary).__name__}")
    return boundary


def boundary_to_dict(boundary: BroadbandBoundary) -> dict:
    """Plain-data form of a boundary (lists of floats; complex poles as [re, im] pairs).

    Parameters
    ----------
    boundary : BroadbandBoundary
        The fitted boundary.
    """
    b = _check_boundary(boundary)
    ss = b.state_space()
    return {
        "format": FORMAT, "version": VERSION, "track": b.track_name, "band_hz": list(b.band),
        "median_error": b.median_error, "max_error": b.max_error, "enforcement_rounds": b.enforcement_rounds,
        "poles": [[p.real, p.imag] for p in b.model.poles],
        "coefficients": b.model.coefficients.tolist(), "K0": b.model.K0.tolist(), "D": b.model.D.tolist(),
        "state_space": {"A": ss.A.tolist(), "B": ss.B.tolist(), "C": ss.C.tolist(), "D": ss.D.tolist(),
                        "K0": ss.K0.tolist(), "dofs": list(ss.dofs)},
        "units": UNITS,
    }


def _array(data: dict, key: str, source: str) -> np.ndarray:
    try:
        out = np.asarray(data[key], dtype=float)
    except KeyError:
        raise InputError(f"{source}: missing key {key!r}") from None
    except (TypeError, ValueError):
        raise InputError(f"{source}: {key!r} must be an array of numbers") from None
    if not np.all(np.isfinite(out)):
        raise InputError(f"{source}: {key!r} must be finite")
    return out


def boundary_from_dict(data: dict, source: str = "data") -> BroadbandBoundary:
    """Rebuild a boundary from :func:`boundary_to_dict` output; the passivity test is re-run.

    Parameters
    ----------
    data : dict
        The plain data.
    source : str
        Name of the data's origin, quoted in error messages.
    """
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f"{source}: not a {FORMAT} file (its 'format' must be {FORMAT!r})")
    poles = _array(data, "poles", source)
    if poles.ndim != 2 or poles.shape[1] != 2:
        raise InputError(f"{source}: 'poles' must be a list of [re, im] pairs")
    try:
        model = RationalEndStiffness(poles[:, 0] + 1j * poles[:, 1], _array(data, "coefficients", source),
                                     _array(data, "K0", source), _array(data, "D", source))
    except ValueError as exc:
        raise InputError(f"{source}: {exc}") from None
    stored = data.get("state_space")
    if isinstance(stored, dict):
        ss = model.state_space()
        for key in ("A", "B", "C", "D", "K0"):
            if not np.allclose(_array(stored, key, source), getattr(ss, key), rtol=1e-9, atol=0):
                raise InputError(f"{source}: state_space[{key!r}] does not match the poles and coefficients")
    band = tuple(float(x) for x in _array(data, "band_hz", source))
    errors = ErrorSummary(median=float(data.get("median_error", np.nan)), max=float(data.get("max_error", np.nan)),
                          per_element={})
    return BroadbandBoundary(model=model, band=band, errors=errors, passivity=passivity_report(model),
                             track_name=str(data.get("track", "")),
                             enforcement_rounds=int(data.get("enforcement_rounds", 0)))


def save_boundary(boundary: BroadbandBoundary, path) -> Path:
    """Write a boundary to ``path``: ``.json`` (exact round trip) or ``.mat`` (MATLAB).

    Parameters
    ----------
    boundary : BroadbandBoundary
        The fitted boundary.
    path : str or Path
        Output file; its suffix selects the format. Written atomically.
    """
    data = boundary_to_dict(boundary)
    suffix = Path(path).suffix.lower()
    if suffix == ".json":
        return atomic_write(path, lambda fh: json.dump(data, fh, indent=1), binary=False)
    if suffix == ".mat":
        ss = data["state_space"]
        mat = {"A": np.array(ss["A"]), "B": np.array(ss["B"]), "C": np.array(ss["C"]), "D": np.array(ss["D"]),
               "K0": np.array(ss["K0"]), "poles": boundary.model.poles[:, None],
               "coefficients": boundary.model.coefficients, "band_hz": np.array(data["band_hz"]),
               "median_error": data["median_error"], "max_error": data["max_error"],
               "enforcement_rounds": data["enforcement_rounds"],
               "format": FORMAT, "units": json.dumps(UNITS), "track": data["track"]}
        return atomic_write(path, lambda fh: scipy.io.savemat(fh, mat), binary=True)
    raise InputError(f"path must end in .json or .mat, got {str(path)!r}")


def load_boundary(path) -> BroadbandBoundary:
    """Read a boundary written by :func:`save_boundary` (``.json`` or ``.mat``).

    Parameters
    ----------
    path : str or Path
        The file.
    """
    path = Path(path)
    if path.suffix.lower() == ".json":
        with open(path, encoding="utf-8") as fh:
            return boundary_from_dict(json.load(fh), source=str(path))
    if path.suffix.lower() == ".mat":
        m = scipy.io.loadmat(path, squeeze_me=False)
        poles = np.asarray(m["poles"]).ravel()
        data = {"format": str(np.asarray(m["format"]).ravel()[0]), "poles": np.c_[poles.real, poles.imag].tolist(),
                "coefficients": m["coefficients"], "K0": m["K0"], "D": m["D"], "band_hz": np.ravel(m["band_hz"]),
                **{key: np.ravel(m[key])[0] for key in ("median_error", "max_error", "enforcement_rounds") if key in m},
                "track": str(np.asarray(m["track"]).ravel()[0]) if np.asarray(m["track"]).size else "",
                "state_space": {k: m[k] for k in ("A", "B", "C", "D", "K0")}}
        return boundary_from_dict(data, source=str(path))
    raise InputError(f"path must end in .json or .mat, got {str(path)!r}")
