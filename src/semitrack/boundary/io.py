"""Export and import of a broadband boundary: JSON (exact round trip) and MATLAB .mat.

Both formats carry the full model (poles, coefficients, ``K0``, ``D``), its real state space
(``A, B, C, D, K0``: what a user's own time-domain code needs), the fit band, the median and
maximum errors, the passivity-enforcement rounds, and the units (the per-element errors, the
orders tried and the fit time are not kept). Loading rebuilds the model from poles and
coefficients and checks that the stored state space agrees with it, so a hand-edited or
mismatched file is refused rather than trusted.

Both also carry the conventions of every end file (:func:`semitrack.equivalent.exchange.end_conventions`:
the semi-infinite track to the right of the cut, ``(Q, M)`` applied to the end so that the force
on the user's node is ``-(Q, M)``, psi, the mirror ``P = diag(1, -1)`` of a left end, the ports,
units, the track and band), in fields and in words; the .mat file also holds the end's M, C, K
(:meth:`~.fitting.BroadbandBoundary.matrix_system`) in the struct ``second_order`` (its ``C`` is the
state space's output matrix); the M, C, K form alone, ``export_boundary(b, "end.mat", mck=True)``,
holds them as ``M``, ``C``, ``K``.
:func:`export_boundary` writes a boundary in any format, the M, C, K ones (``.csv``, Nastran
``.bdf``, Abaqus ``.inp``, and JSON or MAT with ``mck=True``) included. Floats are written in full
(JSON's repr: 17 significant digits; .mat: doubles).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import scipy.io

from ..base.checks import check_flag
from ..base.errors import InputError, InputTypeError
from ..base.files import atomic_write, file_suffix
from ..equivalent.exchange import MATRIX_SUFFIXES, end_conventions, mat_conventions, refuse_labels, save_matrix_system
from ..equivalent.metrics import ErrorSummary
from .fitting import BroadbandBoundary
from .passivity import passivity_report
from .rational import RationalEndStiffness
from .synthesis import SynthesisError
from .validation import check_boundary_data, check_boundary_physics, read_boundary_file

__all__ = ["boundary_to_dict", "boundary_from_dict", "save_boundary", "load_boundary", "export_boundary",
           "STATE_SPACE_SUFFIXES"]

#: The suffixes of the state-space boundary files (the others write the end's M, C, K).
STATE_SPACE_SUFFIXES = (".json", ".mat")

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
        "poles": [[p.real, p.imag] for p in b.rational.poles],
        "coefficients": b.rational.coefficients.tolist(), "K0": b.rational.K0.tolist(), "D": b.rational.D.tolist(),
        "state_space": {"A": ss.A.tolist(), "B": ss.B.tolist(), "C": ss.C.tolist(), "D": ss.D.tolist(),
                        "K0": ss.K0.tolist(), "dofs": list(ss.dofs)},
        "units": UNITS,
        "conventions": end_conventions(b.track_name, b.band, b.track_damping),
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
    if check_flag("check", check):
        check_boundary_physics(model, passivity, source)
    errors = ErrorSummary(median=v["median_error"], max=v["max_error"], per_element={})
    return BroadbandBoundary(rational=model, band=v["band"], errors=errors, passivity=passivity,
                             track_name=v["track"], track_damping=v["track_damping"],
                             enforcement_rounds=v["enforcement_rounds"])


def save_boundary(boundary: BroadbandBoundary, path, format: str | None = None) -> Path:
    """Write a boundary to ``path``: ``.json`` (exact round trip) or ``.mat`` (MATLAB).

    Parameters
    ----------
    boundary : BroadbandBoundary
        The fitted boundary.
    path : str or Path
        Output file; its suffix selects the format unless ``format`` is given. Written atomically.
    format : {"json", "mat"}, optional
        The format, whatever the suffix.
    """
    suffix = file_suffix(path, format)
    data = boundary_to_dict(boundary)
    if suffix == ".json":
        return atomic_write(path, lambda fh: json.dump(data, fh, indent=1), binary=False)
    if suffix == ".mat":
        ss = data["state_space"]
        mat = {"A": np.array(ss["A"]), "B": np.array(ss["B"]), "C": np.array(ss["C"]), "D": np.array(ss["D"]),
               "K0": np.array(ss["K0"]), "poles": boundary.rational.poles[:, None],
               "coefficients": boundary.rational.coefficients, "band_hz": np.array(data["band_hz"]),
               "median_error": data["median_error"], "max_error": data["max_error"],
               "enforcement_rounds": data["enforcement_rounds"],
               "format": FORMAT, "units": json.dumps(UNITS), "track": data["track"],
               "conventions_json": json.dumps(data["conventions"]), "conventions": mat_conventions(data["conventions"]),
               **_second_order_variables(boundary)}
        return atomic_write(path, lambda fh: scipy.io.savemat(fh, mat), binary=True)
    raise InputError(f"format must be json or mat (or path end in .json or .mat), got {suffix!r} for {str(path)!r}")


def _second_order_variables(boundary: BroadbandBoundary) -> dict:
    """The struct ``second_order`` of a .mat file: ``M``, ``C``, ``K`` and ``dof_names`` of the end's
    second-order form (``C`` at the top level is the state space's output matrix), or only a note
    for a model that has none (one that is not passive)."""
    try:
        system = boundary.matrix_system()
    except SynthesisError as exc:
        return {"second_order": {"note": f"no M, C, K: {exc}"}}
    M, C, K = system.matrices()
    return {"second_order": {"M": M, "C": C, "K": K, "dof_names": np.array(system.dof_names(), dtype=object),
                             "note": "the end in second-order form (BroadbandBoundary.matrix_system): ports (w, psi) "
                                     "first; implicit integrators only (massless DOFs)"}}


def export_boundary(boundary: BroadbandBoundary, path, format: str | None = None, mck: bool = False, *,
                    node: int | None = None, first_label: int | None = None) -> Path:
    """Write a boundary in any format: its state space (``.json``, ``.mat``) or its M, C, K.

    Parameters
    ----------
    boundary : BroadbandBoundary
        The fitted boundary.
    path : str or Path
        Output file, written atomically.
    format : {"json", "mat", "csv", "bdf", "inp"}, optional
        The format; default: from the suffix of ``path``.
    mck : bool
        Write the second-order form (:meth:`~.fitting.BroadbandBoundary.matrix_system`) also as
        ``.json`` or ``.mat``; ``.csv``, ``.bdf`` and ``.inp`` always hold it.
    node, first_label : int, optional
        ``.bdf`` and ``.inp``: the node carrying the ports and the first internal DOF's label
        (:func:`semitrack.export_system`).

    Returns
    -------
    Path

    Warns
    -----
    UserWarning
        A ``.bdf`` or ``.inp`` file of an end fitted to a hysteretic track.
    """
    b, mck = _check_boundary(boundary), check_flag("mck", mck)
    key = file_suffix(path, format)
    if key not in MATRIX_SUFFIXES:
        raise InputError(f"format must be one of {', '.join(x[1:] for x in MATRIX_SUFFIXES)} (or a path with that "
                         f"suffix), got {format if format is not None else Path(path).suffix!r}")
    if key in STATE_SPACE_SUFFIXES and not mck:
        refuse_labels(key, node, first_label)
        return save_boundary(b, path, format=key)
    return save_matrix_system(b.matrix_system(), path, format=key, node=node, first_label=first_label)


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
    check = check_flag("check", check)  # before the file is read
    return boundary_from_dict(read_boundary_file(path), source=str(path), check=check)
