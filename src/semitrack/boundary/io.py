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
from .validation import check_boundary_data, check_boundary_physics, read_boundary_file

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


def boundary_from_dict(data: dict, source: str = "data", check: bool = True) -> BroadbandBoundary:
    """Rebuild a boundary from :func:`boundary_to_dict` output, checked; the passivity test is re-run.

    Parameters
    ----------
    data : dict
        The plain data.
    source : str
        Name of the data's origin, quoted in error messages.
    check : bool
        Refuse a model that is unstable, has a static stiffness that is not positive definite or
        fails the exact passivity test (:func:`~.validation.check_boundary_physics`). ``False``
        (for experts) builds it anyway, to inspect it: such a model still cannot close an FE
        track, whose boundary end makes the same checks. The structure and values are checked
        in either case (:func:`~.validation.check_boundary_data`).

    Returns
    -------
    BroadbandBoundary

    Raises
    ------
    InputError
        Naming the source, the key or the check that failed.
    """
    v = check_boundary_data(data, source, FORMAT, VERSION)
    try:
        model = RationalEndStiffness(v["poles"], v["coefficients"], v["K0"], v["D"])
    except ValueError as exc:
        raise InputError(f"{source}: {exc}") from None
    if v["state_space"] is not None:
        ss = model.state_space()
        for key, stored in v["state_space"].items():
            theirs = getattr(ss, key)
            if stored.shape != theirs.shape or not np.allclose(stored, theirs, rtol=1e-9, atol=0):
                raise InputError(f"{source}: state_space[{key!r}] does not match the poles and coefficients")
    passivity = passivity_report(model)
    if check:
        check_boundary_physics(model, passivity, source)
    errors = ErrorSummary(median=v["median_error"], max=v["max_error"], per_element={})
    return BroadbandBoundary(model=model, band=v["band"], errors=errors, passivity=passivity,
                             track_name=v["track"], enforcement_rounds=v["enforcement_rounds"])


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


def load_boundary(path, check: bool = True) -> BroadbandBoundary:
    """Read a boundary written by :func:`save_boundary` (``.json`` or ``.mat``), checked completely.

    The file's size is bounded before it is parsed, and every field is checked (structure, types,
    shapes, the number of poles, values) before a model is built (:mod:`.validation`); then the
    model's physics: stable poles, ``K0`` positive definite, the exact passivity test.

    Parameters
    ----------
    path : str or Path
        The file.
    check : bool
        ``False`` (for experts) loads a model that fails the physics checks, to inspect it (see
        :func:`boundary_from_dict`); files that are damaged or malformed are refused in either case.

    Returns
    -------
    BroadbandBoundary

    Raises
    ------
    InputError
        One line naming the file and the key or check that failed.
    OSError
        If the file cannot be read.
    """
    return boundary_from_dict(read_boundary_file(path), source=str(path), check=check)
