"""The ``semitrack`` command-line program: example, receptance, decay, fit, export, features, run.

Exit codes: 0 success, 2 bad input (a one-line message on stderr, no traceback), 1 unexpected
failure (with a traceback, so that it can be reported), 130 interrupted (Ctrl-C, SIGINT), 143
terminated (SIGTERM). Results go to files written atomically or to stdout; progress goes to
stderr, and only when stderr is a terminal.

Bad input is whatever the package refuses: a :class:`ValueError` raised by the package's own code
(its checks name the parameter, the value and the rule; a ValueError from a library it calls is
a failure), an input or output file that cannot be read or written (:class:`OSError`), and the
command line's own checks. Every output path is checked before the work starts
(:func:`semitrack.base.files.check_output_path`), and the files are written by
:func:`semitrack.base.files.atomic_write`: a symbolic link is written through, a FIFO, device or
directory is refused, and an interruption leaves no temporary file.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import functools
import io
import json
import os
import re
import signal
import sys
import threading
import traceback
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import __version__
from .base.checks import MAX_FREQUENCIES, check_band, check_int_at_least, check_positive, check_work
from .base.conventions import ALL_ELEMENTS, ELEMENT_UNITS, ELEMENTS
from .base.errors import BadInput, caused_by_interrupt
from .base.errors import InputError as PackageInputError
from .base.files import atomic_write, check_input_path, check_output_path, read_text
from .base.paper_values import FIT_BANDS, PAPER_GRID_BAND, PAPER_GRID_STEP
from .base.progress import Progress, silenced
from .equivalent.io import export_system, load_system_json, save_system_json
from .model.trackfile import EXAMPLES, TrackFileError, example_path, load_track_toml
from .model.tracks import Track, ballasted_track, slab_track

if TYPE_CHECKING:  # imported when used, so that --help and bad input answer fast
    import pandas as pd
    from matplotlib.figure import Figure

    from .equivalent.systems import EquivalentSystem

#: Lowest and highest frequency the CLI accepts (Hz): below 1 mHz a track's response is its static
#: one (and the exact method's scaling underflows near 1e-95 Hz), above 1 MHz no beam model of a rail holds.
MIN_FREQUENCY = 1e-3
MAX_FREQUENCY = 1e6
BLOCK = 50  # frequencies per progress step
#: Formats of ``receptance --plot``, by file suffix (matplotlib's names).
PLOT_FORMATS = ("png", "pdf", "svg")

#: Unit of the magnitude of each quantity of ``semitrack features`` (those of
#: :class:`semitrack.CentralResponse` and :data:`semitrack.base.conventions.ELEMENT_UNITS`).
QUANTITY_UNITS: dict[str, str] = {"w1": "m/N", "psi2": "rad/(N m)", "Q2": "N/(N m)", "M1": "N m/N", "det": "N^2",
                                  **ELEMENT_UNITS}


class InputError(PackageInputError):
    """Bad input from the command line or an input file: reported with exit code 2."""


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that ``finally`` blocks (temporary files) run; exit 143."""


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error message (exit code 2 as usual)."""

    def error(self, message):
        # argparse quotes the arguments it did not recognise as typed: a newline in one would split the line
        one_line = message.replace("\r", "\\r").replace("\n", "\\n")
        self.exit(2, f"{self.prog}: error: {one_line}\n")


# ------------------------------------------------------------------------------------------
def checked(check: Callable, *args):
    """Run one of the package's checks (:mod:`semitrack.base.checks`); its error becomes an InputError."""
    try:
        return check(*args)
    except (TypeError, ValueError) as err:
        raise InputError(str(err)) from None


class Typed(float):
    """A number from the command line that messages quote as it was typed (``1e309``, not ``inf``)."""

    def __new__(cls, text: str):
        number = super().__new__(cls, text)
        number.text = text.strip()
        return number

    def __repr__(self) -> str:
        return self.text


#: A number as the command line takes it: decimal digits, a point, an exponent (no "1_0", which Python reads as 10).
_NUMBER = re.compile(r"\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*|\s*[+-]?(inf|infinity|nan)\s*", re.IGNORECASE)
_INTEGER = re.compile(r"\s*[+-]?\d+\s*")


def number(text: str) -> Typed:
    """argparse's converter of numbers (its error reads "invalid number value: 'abc'")."""
    if not _NUMBER.fullmatch(text):
        raise PackageInputError(text)  # a ValueError: argparse reports it as an invalid number
    return Typed(text)


def integer(text: str) -> int:
    """argparse's converter of integers: digits only (its error reads "invalid integer value: '1_0'")."""
    if not _INTEGER.fullmatch(text):
        raise PackageInputError(text)
    return int(text)


def frequency(name: str, value: float) -> float:
    """A frequency from the command line (Hz): finite, from :data:`MIN_FREQUENCY` to :data:`MAX_FREQUENCY`."""
    checked(check_positive, name, value)
    if not MIN_FREQUENCY <= value <= MAX_FREQUENCY:
        raise InputError(f"{name} must be from {MIN_FREQUENCY:g} to {MAX_FREQUENCY:g} Hz, got {value!r}")
    return float(value)


def frequency_grid(fmin: float, fmax: float, df: float) -> np.ndarray:
    """The grid fmin, fmin + df, ... up to fmax inclusive (Hz); checks the three numbers."""
    checked(check_positive, "--df", df)
    if frequency("--fmin", fmin) > frequency("--fmax", fmax):
        raise InputError(f"--fmin must not exceed --fmax, got fmin={fmin!r} > fmax={fmax!r}")
    fmin, fmax, df = float(fmin), float(fmax), float(df)
    n = np.floor((fmax - fmin) / df + 1e-9) + 1  # a float: a tiny --df makes it huge (or inf)
    checked(check_work, n, MAX_FREQUENCIES, f"the grid would hold {n:.3g} frequencies", "increase --df")
    return fmin + df * np.arange(int(n))


def _description(load: Callable, path: str, name: str):
    """``load(path)`` of a TOML description file (track or vehicle); its located error is bad input."""
    checked(check_input_path, path, name)
    try:
        return load(path)
    except TrackFileError as err:
        raise InputError(str(err)) from None


def _track(path: str) -> Track:
    return _description(load_track_toml, path, "track")


def track_kind(track: Track) -> str:
    """What carries the pads of ``track``, for the labels of the results.

    Parameters
    ----------
    track : Track
        The track.

    Returns
    -------
    str
        ``"rigid slab"`` (the paper's slab track), ``"sleepers on ballast"``, ``"measured
        foundation"``, or for a flexible slab ``"flexible slab, S fasteners per L m slab, cut at
        ..."``: where alpha's cut sits matters on a flexible slab (a slab joint, the slab's centre
        or the k-th mid-span inside); ``", frequency-dependent pad"`` follows where kv or kphi is
        a curve.
    """
    pad = ", frequency-dependent pad" if {"kv", "kphi"} & set(track.curves) else ""
    if track.is_ballasted:
        return "sleepers on ballast" + pad
    if track.foundation is not None:
        return "measured foundation" + pad
    if not track.has_flexible_slab:
        return "rigid slab" + pad
    slab = track.slab
    k = slab.cut_span
    cut = "a slab joint" if k == 0 else "the slab centre" if slab.cut == "centre" else f"mid-span {k} of the slab"
    return f"flexible slab, {slab.fasteners} fasteners per {slab.length:g} m slab, cut at {cut}"


def output_paths(*named: tuple[str, str | None], inputs: tuple[tuple[str, str], ...] = ()) -> list[Path | None]:
    """Check every output file before the work starts: each writable, no file named twice, no input replaced.

    Parameters
    ----------
    *named : tuple of (str, str or None)
        ``(option, path)`` pairs, e.g. ``("-o", "alpha.csv")``; a None path (not asked for) is skipped.
    inputs : tuple of (str, str)
        ``(what, path)`` of every file the command reads (:func:`input_files`): an output that is
        one of them, by any name (the same path, a symbolic or a hard link; compared with
        :func:`os.path.samefile`), is refused, since writing it would replace the input.

    Returns
    -------
    list of Path or None
        The paths as given, in order (None where none was given).
    """
    seen: dict[Path, str] = {}
    for option, path in named:
        if path is None:
            continue
        target = checked(check_output_path, path, option)
        if target.resolve() in seen:
            raise InputError(f"{option} and {seen[target.resolve()]} name the same file {path!r}: name two files")
        seen[target.resolve()] = option
        for what, source in inputs:
            if target.exists() and os.path.exists(source) and os.path.samefile(target, source):
                raise InputError(f"{option} {path!r} is the {what} {source!r}: writing it would replace the "
                                 "input; name another file")
    return [None if path is None else Path(path) for _, path in named]


def input_files(track_path: str, track: Track) -> tuple[tuple[str, str], ...]:
    """The files a track command reads: the track file and the tables it names (pads, foundation).

    Parameters
    ----------
    track_path : str
        The track file as given.
    track : Track
        The track read from it.

    Returns
    -------
    tuple of (str, str)
        ``(what, path)`` pairs for :func:`output_paths`.
    """
    curves = [track.foundation, *track.curves.values()]
    tables = tuple(("table", curve.file) for curve in curves if isinstance(getattr(curve, "file", None), str))
    return (("track file", track_path), *tables)


def plot_format(path: Path) -> str:
    """The format of ``--plot`` from its file suffix, one of :data:`PLOT_FORMATS`."""
    suffix = path.suffix.lower().lstrip(".")
    if suffix not in PLOT_FORMATS:
        raise InputError(f"--plot {str(path)!r}: cannot tell the format from its suffix; name a "
                         f"{', '.join('.' + f for f in PLOT_FORMATS)} file")
    return suffix


def stdout():
    """sys.stdout, to write results to; refused (exit 2) before any work when it is closed."""
    if sys.stdout is None:  # started with stdout closed (e.g. `>&-`)
        raise InputError("stdout is closed: there is nowhere to write the results (redirect it, e.g. > out.csv)")
    return sys.stdout


def emit(text: str) -> None:
    """Write results to stdout; a full disk or another write error is bad input (exit 2)."""
    try:
        stdout().write(text)
        stdout().flush()
    except BrokenPipeError:
        raise
    except OSError as err:
        _silence_stdout()  # what stays in the buffer would fail again at exit (exit 120, a traceback)
        raise InputError(f"cannot write to stdout ({err.strerror})") from None


def printable(text: str) -> str:
    """``text`` with its line breaks and other control characters escaped (``\\n``): one line."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


# ------------------------------------------------------------------------------------------
def receptance_csv(track: Track, f: np.ndarray, alpha: np.ndarray, method: str) -> str:
    """CSV text of a receptance sweep: header comments with units and signs, then one row per f.

    The columns are ``f_Hz`` and, for each element of
    :data:`semitrack.base.conventions.ALL_ELEMENTS`, its real part, imaginary part, magnitude and
    phase (``alpha11_re``, ``alpha11_im``, ``alpha11_abs``, ``alpha11_phase``, ...).
    """
    buf = io.StringIO()
    buf.write(f"# semitrack {__version__}: receptance at the end of the semi-infinite track "
              f"'{printable(track.name)}' ({track_kind(track)}; method={method})\n")
    units = ", ".join(f"{name} in {ELEMENT_UNITS[name]}" for name in ALL_ELEMENTS)
    buf.write(f"# units: f in Hz; {units} (alpha12 = w/M, alpha21 = psi/Q); phase in rad\n")
    buf.write("# sign convention: w downward, psi clockwise; end force Q downward, end moment M clockwise; "
              "time factor exp(i omega t); [[alpha11, alpha12], [alpha21, alpha22]] = (w, psi) per (Q, M)\n")
    cols = ["f_Hz"] + [f"{name}_{part}" for name in ALL_ELEMENTS for part in ("re", "im", "abs", "phase")]
    buf.write(",".join(cols) + "\n")
    parts = [f[:, None]]
    for i, k in ALL_ELEMENTS.values():
        a = alpha[:, i, k]
        parts.append(np.column_stack([a.real, a.imag, np.abs(a), np.angle(a)]))
    np.savetxt(buf, np.hstack(parts), delimiter=",", fmt="%.12e")
    return buf.getvalue()


def receptance_figure(track: Track, f: np.ndarray, alpha: np.ndarray) -> Figure:
    """The figure of ``semitrack receptance --plot``: |alpha11|, |alpha12|, |alpha22| against f.

    Parameters
    ----------
    track : Track
        The track (its name goes in the title).
    f : ndarray
        Frequencies (Hz).
    alpha : ndarray
        Receptance at ``f``, shape ``(n, 2, 2)``, in the units of
        :data:`semitrack.base.conventions.ELEMENT_UNITS`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from .plotting.receptance import receptance_figure as draw  # the book's figure; no backend selected

    fig, _ = draw(f, {track.name: alpha}, title=f"Semi-infinite track '{track.name}': end receptance")
    return fig


def _plot_receptance(path: Path, track: Track, f: np.ndarray, alpha: np.ndarray) -> None:
    fig = receptance_figure(track, f, alpha)
    atomic_write(path, lambda fh: fig.savefig(fh, format=plot_format(path), dpi=110), binary=True)


def cmd_receptance(args: argparse.Namespace) -> int:
    from .methods.receptance import frequency_blocks, semi_infinite_receptance

    track = _track(args.track)
    if args.method == "wavenumber" and track.has_flexible_slab and track.slab.cut_span != 0:
        # the package says this in Python's words (method=, cut=): say it in the CLI's
        raise InputError(f"--method wavenumber cannot give alpha at a cut inside the slab (cut = {track.slab.cut!r} "
                         "in [slab]): the paper's Eq. (14) ignores the slab the two halves share; use "
                         "--method transfer, or cut = \"joint\" in the track file")
    f = frequency_grid(args.fmin, args.fmax, args.df)
    out, plot = output_paths(("-o", None if args.output == "-" else args.output), ("--plot", args.plot),
                             inputs=input_files(args.track, track))
    if plot is not None:
        plot_format(plot)
    if out is None:
        stdout()
    frequency_blocks(track.cell(), f, "--fmin, --fmax, --df")  # the whole grid's work, before its first block
    progress = Progress("receptance", int(np.ceil(f.size / BLOCK)), quiet=args.quiet)
    blocks = []
    for n, start in enumerate(range(0, f.size, BLOCK), start=1):
        blocks.append(semi_infinite_receptance(track, f[start : start + BLOCK], method=args.method))
        progress.update(n)
    progress.close()
    alpha = np.concatenate(blocks)
    text = receptance_csv(track, f, alpha, args.method)
    if out is None:
        emit(text)
    else:
        atomic_write(out, lambda fh: fh.write(text), binary=False)
    if plot is not None:
        _plot_receptance(plot, track, f, alpha)
    return 0


def decay_csv(track: Track, tdr, changed: int = 0) -> str:
    """The CSV of ``semitrack decay``: a row per band, with the standard's checks (``changed``: the
    number of supports the track file's ``[[changes]]`` change, said in the header)."""
    buf = io.StringIO()
    changes = (f", {changed} changed support{'s' * (changed != 1)}; the grid runs in +x from the accelerometer at "
               "x = 0" if changed else "")
    buf.write(f"# track decay rate of {printable(track.name)!r} ({track_kind(track)}{changes}), EN 15461 grid and "
              "Formula 1, "
              f"{tdr.frf} averaged over lines {tdr.df:g} Hz apart; Formula 2 floor {tdr.floor:.4f} dB/m\n")
    buf.write("# band_Hz: the nominal one-third-octave band (IEC 61260), centre_Hz its exact centre; valid: suitable "
              "(floor <= rate / 2) and a far-point drop >= 10 dB; wave: the least attenuated Bloch wave at the "
              "centre\n")
    verdict = tdr.meets()
    failing = [f"{b:g}" for b, ok in verdict.items() if not ok]
    buf.write("# iso3095_limit_dB_per_m: the ISO 3095 lower limit (empty below 250 Hz, where it sets none); "
              f"meets_iso3095: rate >= limit; {len(failing)} of {len(verdict)} judged bands fail"
              f"{': ' + ' '.join(failing) + ' Hz' if failing else ''}\n")
    buf.write("band_Hz,centre_Hz,decay_rate_dB_per_m,wave_dB_per_m,far_point_drop_dB,suitable,valid,"
              "iso3095_limit_dB_per_m,meets_iso3095\n")
    limits = tdr.limits()
    for row in zip(tdr.nominal, tdr.centres, tdr.decay_rate, tdr.wave_attenuation, tdr.far_point_drop, tdr.suitable,
                   tdr.valid, limits):
        judged = row[0] in verdict
        limit, meets = (f"{row[7]:g}", str(int(verdict[row[0]]))) if judged else ("", "")
        buf.write(f"{row[0]:g},{row[1]:.6g},{row[2]:.6g},{row[3]:.6g},{row[4]:.6g},{int(row[5])},{int(row[6])},"
                  f"{limit},{meets}\n")
    return buf.getvalue()


def cmd_decay(args: argparse.Namespace) -> int:
    from .methods.decay import ISO3095_TDR_LIMIT, track_decay_rate
    from .methods.infinite import InfiniteTrack

    track, local = _track_with_changes(args.track)
    if local.gaps:
        raise InputError(f"{args.track}: a gap under a sleeper ([[changes]] gap =) is a contact of a run in time "
                         "(semitrack run); the decay rate takes the hanging sleeper as kb = 0.0: remove the gap")
    band = None
    if args.band is not None:
        band = checked(check_band, args.band, "--band")
        frequency("--band", band[0]), frequency("--band", band[1])
    checked(check_positive, "--df", args.df)
    out, plot = output_paths(("-o", None if args.output == "-" else args.output), ("--plot", args.plot),
                             inputs=input_files(args.track, track))
    if plot is not None:
        plot_format(plot)
    if track.has_flexible_slab:
        raise InputError("semitrack decay takes a track without a flexible slab ([slab]): the decay rate's exact "
                         "transfer functions are InfiniteTrack's, which holds pads on a rigid foundation or sleepers")
    tdr = track_decay_rate(InfiniteTrack(track, local.changes) if local.changes else track, band=band, df=args.df,
                           frf=args.frf)
    text = decay_csv(track, tdr, len(local.changes))
    if out is None:
        stdout()
        emit(text)
    else:
        atomic_write(out, lambda fh: fh.write(text), binary=False)
    if plot is not None:
        from .plotting.decay import decay_rate_figure

        fig, _ = decay_rate_figure({track.name: tdr}, ISO3095_TDR_LIMIT)
        atomic_write(plot, lambda fh: fig.savefig(fh, format=plot_format(plot), dpi=110), binary=True)
    return 0


def cmd_fit(args: argparse.Namespace) -> int:
    from .boundary.fitting import DEFAULT_BOUNDARY_BAND

    track = _track(args.track)
    if args.band is None and not args.boundary:
        raise InputError("--band is needed for an equivalent system's fit, which holds only in its band (the "
                         "paper's: --band {:g} {:g} on the slab track, {:g} {:g} on the ballasted); --boundary "
                         "fits {:g}-{:g} Hz by default".format(*FIT_BANDS["slab"], *FIT_BANDS["ballasted"],
                                                               *DEFAULT_BOUNDARY_BAND))
    band = list(DEFAULT_BOUNDARY_BAND) if args.band is None else args.band
    fmin, fmax = checked(check_band, band, "--band")
    frequency("--band", band[0]), frequency("--band", band[1])
    checked(check_int_at_least, "--seed", args.seed, 0)
    (out,) = output_paths(("-o", args.output), inputs=input_files(args.track, track))
    _fit_options_agree(args)
    if args.boundary:
        return _fit_boundary(args, track, (fmin, fmax), out)
    if args.mck:
        raise InputError("--mck applies with --boundary (a fitted system's file holds its M, C, K already)")
    from .equivalent.fitting import fit_equivalent

    args.bars = 5 if args.bars is None else args.bars
    checked(check_int_at_least, "--bars", args.bars, 1)
    layout = args.layout or ("ballasted" if track.is_ballasted or track.foundation is not None else "slab")
    progress = Progress("fit", 1, quiet=args.quiet)
    progress.update(0, f"fitting N = {args.bars} bars, {layout} layout")
    fit = fit_equivalent(track, layout=layout, n_bars=args.bars, band=(fmin, fmax), seed=args.seed,
                         constrained=not args.unconstrained)
    progress.update(1)
    progress.close()
    save_system_json(fit.system, out, track=track.name, band=(fmin, fmax), track_damping=track.damping)
    bars = f"{args.bars} bar" + "s" * (args.bars != 1)
    print(f"fitted a {layout} equivalent system with {bars} to '{printable(track.name)}' ({track_kind(track)}) "
          f"over {fmin:g}-{fmax:g} Hz")
    print(f"median relative error {fit.median_error:.4f}, maximum {fit.max_error:.4f} ({', '.join(ELEMENTS)})")
    print(f"written to {out}")
    return 0


#: The formats of an end file, by suffix: a boundary's state space (json, mat) or any end's M, C, K.
END_FORMATS = ("json", "mat", "csv", "bdf", "inp")


def _fit_options_agree(args: argparse.Namespace) -> None:
    """Refuse options of one kind of fit given to the other (they would be silently ignored)."""
    if args.boundary:
        given = [name for name, value in (("--bars", args.bars), ("--layout", args.layout)) if value is not None]
        given += ["--unconstrained"] if args.unconstrained else []
        if given:
            raise InputError(f"{' and '.join(given)} set an equivalent system's fit, not --boundary's (which "
                             "takes --poles): drop them or drop --boundary")
    elif args.poles is not None:
        raise InputError("--poles sets the order of a --boundary fit: add --boundary, or give an equivalent "
                         "system's --bars instead")
    elif args.node is not None or args.first_label is not None:
        raise InputError("--node and --first-label label a --boundary fit's .bdf or .inp file; an equivalent "
                         "system's JSON names its DOFs: write it, then 'semitrack export system.json -o end.bdf "
                         "--node N'")


def _file_labels(args: argparse.Namespace, fmt: str) -> dict:
    """``--node`` and ``--first-label`` checked, for a .bdf or .inp file only (never ignored)."""
    given = [name for name, value in (("--node", args.node), ("--first-label", args.first_label)) if value is not None]
    if given and fmt not in ("bdf", "inp"):
        raise InputError(f"{' and '.join(given)} label the DOFs of a .bdf or .inp file; a .{fmt} file names them: "
                         "drop them, or write a .bdf or .inp file")
    for name, value in (("--node", args.node), ("--first-label", args.first_label)):
        if value is not None:
            checked(check_int_at_least, name, value, 1)
    return {"node": args.node, "first_label": args.first_label}


def _end_format(out: Path, given: str | None) -> str:
    """The format of an output end file: ``--format`` or the suffix of ``-o``."""
    fmt = given or out.suffix.lower().lstrip(".")
    if fmt not in END_FORMATS:
        raise InputError(f"cannot tell the format from {out.name!r}: give --format {'|'.join(END_FORMATS)} or a "
                         f"{'/'.join('.' + x for x in END_FORMATS)} file name")
    return fmt


def _fit_boundary(args: argparse.Namespace, track: Track, band: tuple[float, float], out: Path) -> int:
    """``semitrack fit --boundary``: the broadband passive end model, in any end format (its state space
    as .json or .mat; its M, C, K as .csv, .bdf, .inp, or .json/.mat with --mck)."""
    from .boundary.fitting import check_n_poles, fit_boundary
    from .boundary.io import export_boundary

    if out.suffix.lower().lstrip(".") not in END_FORMATS:
        raise InputError(f"-o must name a {'/'.join('.' + x for x in END_FORMATS)} file for --boundary, "
                         f"got {out.name!r}")
    if args.poles is not None:
        checked(check_n_poles, args.poles, "--poles")
    progress = Progress("fit", 1, quiet=args.quiet)
    progress.update(0, "fitting a broadband boundary")
    labels = _file_labels(args, out.suffix.lower().lstrip("."))
    bnd = fit_boundary(track, band=band, n_poles=args.poles, seed=args.seed)
    progress.update(1)
    progress.close()
    export_boundary(bnd, out, mck=args.mck, **labels)
    proof = "proven passive" if bnd.passivity else "NOT passive"
    print(f"fitted a broadband boundary with {bnd.n_poles} poles to '{printable(track.name)}' "
          f"({track_kind(track)}) over {band[0]:g}-{band[1]:g} Hz ({proof})")
    print(f"median relative error {bnd.median_error:.4f}, maximum {bnd.max_error:.4f} ({', '.join(ELEMENTS)})")
    print(f"written to {out}")
    return 0


def load_system_file(path: str) -> EquivalentSystem:
    """The system of a JSON file written by ``semitrack fit`` (or :func:`semitrack.export_system`).

    Parameters
    ----------
    path : str
        The file.

    Returns
    -------
    SlabEquivalent or BallastedEquivalent

    Raises
    ------
    InputError
        Naming the file and the key or value at fault.
    """
    try:
        return load_system_json(path)
    except OSError as err:
        raise InputError(f"{path}: cannot read the system file ({err.strerror})") from None
    except KeyError as err:
        raise InputError(f"{path}: cannot load the system: missing key {err.args[0]!r}") from None
    except (TypeError, ValueError) as err:
        message = str(err).removeprefix(f"{path}: ")  # the package's messages name the file already
        raise InputError(f"{path}: cannot load the system: {message}") from None


def _file_header(path: str) -> tuple[str, dict]:
    """The ``format`` an end file declares and its ``conventions`` record (JSON keys, .mat
    variables, or the CSV rows); ``("", {})`` where it has none."""
    suffix = Path(path).suffix.lower()
    try:
        if suffix == ".json":
            from .equivalent.io import MAX_SYSTEM_BYTES

            data = json.loads(read_text(Path(path), MAX_SYSTEM_BYTES, "system file"))
            if not isinstance(data, dict):
                return "", {}
            conventions = data.get("conventions")
            return str(data.get("format", "")), conventions if isinstance(conventions, dict) else {}
        if suffix == ".mat":
            from .base.files import read_mat
            from .equivalent.io import MAX_SYSTEM_BYTES

            raw = read_mat(Path(path), MAX_SYSTEM_BYTES, "system file", simplify=True)
            return str(raw.get("format", "")), _json_or_empty(str(raw.get("conventions_json", "{}")))
        if suffix == ".csv":
            from .equivalent.io import MAX_SYSTEM_BYTES

            rows = list(csv.reader(read_text(Path(path), MAX_SYSTEM_BYTES, "system file").splitlines()))
            fmt = next((row[1].strip() for row in rows if len(row) > 1 and row[0] == "format"), "")
            start = next((i for i, row in enumerate(rows) if row[:1] == ["[conventions]"]), None)
            conventions = {}
            for row in rows[start + 2:] if start is not None else []:
                if not row or row[0].startswith("["):
                    break
                conventions[row[0]] = _json_or_empty(row[1]) if len(row) > 1 else {}
            return fmt, conventions
    except OSError as err:
        raise InputError(f"{path}: cannot read the system file ({err.strerror})") from None
    except PackageInputError:
        raise  # too large, not text, a damaged or inflating .mat file: refused once, not read again
    except (ValueError, RecursionError, IndexError, csv.Error):
        return "", {}  # not JSON, CSV or our layout: the system loader says what is wrong
    return "", {}


def _json_or_empty(text: str):
    """JSON text parsed, or ``{}``: a damaged conventions record must not lose the file's format (its loader,
    chosen by the format, then refuses the record naming it)."""
    try:
        return json.loads(text)
    except (ValueError, RecursionError):
        return {}


def load_end_file(path: str):
    """An end file of any kind: a paper-style system, a broadband boundary, or an end's M, C, K.

    Parameters
    ----------
    path : str
        A ``.json``, ``.mat`` or ``.csv`` file written by the package.

    Returns
    -------
    EquivalentSystem, BroadbandBoundary or MatrixSystem
    """
    from .boundary.io import FORMAT as BOUNDARY_FORMAT
    from .boundary.io import load_boundary
    from .equivalent.exchange import MATRIX_FORMAT, load_matrix_system
    from .equivalent.io import load_system_csv, load_system_mat

    fmt, _ = _file_header(path)
    try:
        if fmt == BOUNDARY_FORMAT:
            return load_boundary(path)
        if fmt == MATRIX_FORMAT:
            return load_matrix_system(path)
        suffix = Path(path).suffix.lower()
        if suffix in (".csv", ".mat"):
            return (load_system_csv if suffix == ".csv" else load_system_mat)(path)
    except (KeyError, TypeError, ValueError) as err:
        message = str(err).removeprefix(f"{path}: ")
        raise InputError(f"{path}: cannot load the system: {message}") from None
    return load_system_file(path)


def cmd_export(args: argparse.Namespace) -> int:
    from .boundary.fitting import BroadbandBoundary
    from .boundary.io import export_boundary

    checked(check_input_path, args.system, "system")
    source = load_end_file(args.system)
    output = args.output
    if output is None:  # beside the input, with the format's suffix
        if args.format is None:
            raise InputError("give -o FILE or --format FORMAT")
        output = str(Path(args.system).with_suffix("." + args.format))
        if Path(output).resolve() == Path(args.system).resolve():
            raise InputError(f"the output {output!r} would replace the input: give -o FILE")
    (out,) = output_paths(("-o", output), inputs=(("system file", args.system),))
    fmt = _end_format(out, args.format)
    labels = _file_labels(args, fmt)
    if isinstance(source, BroadbandBoundary):
        export_boundary(source, out, format=fmt, mck=args.mck, **labels)
        as_mck = ", as M, C, K" if args.mck or fmt in ("csv", "bdf", "inp") else ""
        what = f"a broadband boundary ({source.n_poles} poles{as_mck})"
    else:
        if args.mck:
            raise InputError("--mck applies to a boundary file; a system file is written as M, C, K already")
        conventions = _file_header(args.system)[1]  # the track, band and damping it was fitted on, carried on
        band = conventions.get("band_hz")
        export_system(source, out, format=fmt, track=conventions.get("track") or None,
                      band=band if isinstance(band, list) and len(band) == 2 else None,
                      track_damping=conventions.get("track_damping") or None, **labels)
        what = f"a {source.kind} system with {source.n_dof} DOFs"
    print(f"{fmt} export of {what} written to {out}")
    return 0


def paper_mode_names(track: Track, table: pd.DataFrame) -> list[str]:
    """The paper's name of the mode of each row of a peaks-and-dips table, or "" where it has none.

    The paper names the modes of its two tracks (Tables 3 and 6, Sec. 4-5); a row gets the name
    of each of the paper's entries of its quantity and kind whose nearest extremum it is (within
    10 %, as in :func:`semitrack.paper_frequency_table`). Any other track, even one changed
    parameter away, gets no names: its modes may have moved or changed order. A flexible slab is
    another track too (the paper's slab is rigid): its slab adds modes of its own.

    Parameters
    ----------
    track : Track
        The track of the table.
    table : pandas.DataFrame
        Columns ``quantity, kind, f`` (Hz), as from :func:`semitrack.characteristic_frequencies`.

    Returns
    -------
    list of str
        One name per row, e.g. ``"first pinned-pinned mode (Table 3)"``; several joined by "; ".
    """
    from .paper.frequencies import nearest_extremum, paper_frequencies

    preset = ballasted_track() if track.is_ballasted else slab_track()
    names = [[] for _ in range(len(table))]
    if track.replace(name=preset.name) == preset:  # the whole Track: its slab (None for the paper's) too
        for f_paper, quantity, kind, source, mode in paper_frequencies(track):
            f = nearest_extremum(table, quantity, kind, f_paper, rel_window=0.1)
            rows = np.flatnonzero((table["quantity"] == quantity) & (table["kind"] == kind) & (table["f"] == f))
            for row in rows:
                names[row].append(f"{mode} ({source})")
    return ["; ".join(n) for n in names]


def features_table(track: Track, f: np.ndarray, df: float) -> pd.DataFrame:
    """Peaks and dips of a track's response curves by frequency, with units and the paper's mode names.

    Parameters
    ----------
    track : Track
        The track.
    f : ndarray
        The search grid (Hz), at least 3 points, step ``df``.
    df : float
        Its step (Hz).

    Returns
    -------
    pandas.DataFrame
        Columns ``f_Hz`` (refined), ``f_grid_Hz``, ``quantity``, ``kind``, ``magnitude`` (of the
        quantity at ``f_Hz``), ``unit`` (of the magnitude) and ``mode`` (:func:`paper_mode_names`),
        sorted by frequency.
    """
    from .methods.features import QUANTITIES, characteristic_frequencies

    table = characteristic_frequencies(track, band=(f[0], f[-1]), df=df)
    table["unit"] = table["quantity"].map(QUANTITY_UNITS)
    table["mode"] = paper_mode_names(track, table)
    table["order"] = table["quantity"].map(QUANTITIES.index)  # ties by the order of QUANTITIES
    table = table.sort_values(["f", "order"], ignore_index=True)
    table = table.rename(columns={"f": "f_Hz", "f_grid": "f_grid_Hz"})
    return table[["f_Hz", "f_grid_Hz", "quantity", "kind", "magnitude", "unit", "mode"]]


def cmd_features(args: argparse.Namespace) -> int:
    track = _track(args.track)
    f = frequency_grid(args.fmin, args.fmax, args.df)
    if f.size < 3:
        raise InputError("--fmin, --fmax and --df give fewer than 3 frequencies: peaks and dips need at least 3")
    stdout()
    table = features_table(track, f, args.df)
    if args.csv:
        emit(table.to_csv(index=False, float_format="%.6g"))
        return 0
    lines = [f"peaks and dips of '{printable(track.name)}' ({track_kind(track)}) between {f[0]:g} and {f[-1]:g} Hz "
             "(exact method, refined), rows by frequency, each magnitude in its unit"]
    if table["mode"].eq("").all():
        table = table.drop(columns="mode")
        lines.append("(modes are named for the paper's two tracks only, as the paper names them)")
    else:
        width = table["mode"].str.len().max()
        table["mode"] = table["mode"].str.ljust(width)
    table = table.rename(columns={"f_Hz": "f (Hz)", "f_grid_Hz": "grid f (Hz)"})
    lines.append(table.to_string(index=False, float_format=lambda v: f"{v:.6g}"))
    emit("\n".join(lines) + "\n")
    return 0


def cmd_example(args: argparse.Namespace) -> int:
    from .model.vehiclefile import VEHICLE_EXAMPLES, load_vehicle_toml, vehicle_example_path

    names = ", ".join((*EXAMPLES, *VEHICLE_EXAMPLES))
    stdout()
    if args.list:
        width = max(map(len, (*EXAMPLES, *VEHICLE_EXAMPLES)))
        for name in EXAMPLES:
            track = load_track_toml(example_path(name))
            print(f"{name:<{width}}  track: {track.name} ({track_kind(track)})")
        for name in VEHICLE_EXAMPLES:
            vehicle = load_vehicle_toml(vehicle_example_path(name))
            print(f"{name:<{width}}  vehicle: {type(vehicle).__name__} with {len(vehicle.wheels)} wheel(s)")
        return 0
    if args.name is None:
        raise InputError(f"name an example: {names} (e.g. semitrack example slab > slab.toml)")
    if args.name in VEHICLE_EXAMPLES:
        emit(vehicle_example_path(args.name).read_text())
        return 0
    if args.name not in EXAMPLES:
        raise InputError(f"unknown example {args.name!r}; the examples are: {names}")
    emit(example_path(args.name).read_text())
    return 0


# ------------------------------------------------------------------------------------------
def _track_and_grid_arguments(p: argparse.ArgumentParser, step: str) -> None:
    p.add_argument("track", help="track description file (TOML)")
    (fmin, fmax), df = PAPER_GRID_BAND, PAPER_GRID_STEP  # the paper's grid by default
    p.add_argument("--fmin", type=number, default=fmin, help=f"lowest frequency, Hz (default {fmin:g})")
    p.add_argument("--fmax", type=number, default=fmax, help=f"highest frequency, Hz (default {fmax:g})")
    p.add_argument("--df", type=number, default=df, help=f"{step}, Hz (default {df:g})")


def _example_parser(sub) -> None:
    """The ``example`` command and its arguments, on the subparsers ``sub``."""
    p = sub.add_parser("example", help="print a shipped example track file (the paper's two tracks, and its "
                                       "rail on two flexible slabs) or vehicle file (a bogie, a wheel)",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="examples:\n  semitrack example slab > slab.toml\n"
                              "  semitrack example floating-slab > floating_slab.toml\n  semitrack example --list")
    p.add_argument("name", nargs="?", help=f"which example: {', '.join(EXAMPLES)}, bogie, wheel")
    p.add_argument("--list", action="store_true", help="list the examples")
    p.set_defaults(func=cmd_example)


def _receptance_parser(sub) -> None:
    """The ``receptance`` command and its arguments, on the subparsers ``sub``."""
    p = sub.add_parser("receptance", help="receptance of the semi-infinite track to CSV",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="example:\n  semitrack receptance slab.toml --fmin 3 --fmax 3000 --df 6 -o alpha.csv "
                              "--plot alpha.png")
    _track_and_grid_arguments(p, "frequency step")
    p.add_argument("--method", choices=("transfer", "wavenumber"), default="transfer",
                   help="transfer: exact (default); wavenumber: the paper's method and settings")
    p.add_argument("-o", "--output", default="-", help="CSV file to write (default: stdout)")
    p.add_argument("--plot", help="also write a plot of the magnitudes; its suffix gives the format: "
                                  f"{', '.join('.' + f for f in PLOT_FORMATS)}")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=cmd_receptance)


def _decay_parser(sub) -> None:
    """The ``decay`` command and its arguments, on the subparsers ``sub``."""
    p = sub.add_parser("decay", help="track decay rate by one-third-octave band (EN 15461) to CSV",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="example:\n  semitrack decay ballasted.toml -o tdr.csv --plot tdr.png")
    p.add_argument("track", help="track description file (TOML)")
    p.add_argument("--band", type=number, nargs=2, metavar=("FMIN", "FMAX"), default=None,
                   help="lowest and highest band centres, Hz (default 100 5000, the standard's, less the end bands "
                        "a measured table does not reach)")
    p.add_argument("--df", type=number, default=2.0, help="spacing of the lines averaged in each band, Hz (default 2)")
    p.add_argument("--frf", choices=("accelerance", "mobility", "receptance"), default="accelerance",
                   help="transfer function averaged in the bands (default accelerance, the standard's)")
    p.add_argument("-o", "--output", default="-", help="CSV file to write (default: stdout)")
    p.add_argument("--plot", help="also write a plot beside the ISO 3095 limit; its suffix gives the format: "
                                  f"{', '.join('.' + f for f in PLOT_FORMATS)}")
    p.set_defaults(func=cmd_decay)


def _fit_parser(sub) -> None:
    """The ``fit`` command and its arguments, on the subparsers ``sub``."""
    p = sub.add_parser("fit", help="fit an equivalent multi-rigid-body system or a broadband boundary",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="examples:\n  semitrack fit ballasted.toml --bars 5 --band {:g} {:g} --seed 0 "
                              "-o system.json\n"
                              "  semitrack fit slab.toml --boundary --band 3 3000 -o boundary.json"
                              .format(*FIT_BANDS["ballasted"]))
    p.add_argument("track", help="track description file (TOML)")
    p.add_argument("--bars", type=integer, default=None, help="number of rigid bars N (default 5)")
    p.add_argument("--layout", choices=("slab", "ballasted"), default=None,
                   help="the equivalent system's layout (default: ballasted for sleepers on ballast or a measured "
                        "foundation, whose own dynamics its second mass takes; slab otherwise)")
    p.add_argument("--band", type=number, nargs=2, metavar=("FMIN", "FMAX"), default=None,
                   help="band to fit, Hz (needed for a system; with --boundary default 3 3000)")
    p.add_argument("--seed", type=integer, default=0, help="seed of the multi-start (default 0)")
    p.add_argument("--unconstrained", action="store_true", help="drop the paper's frequency constraints")
    p.add_argument("--boundary", action="store_true",
                   help="fit the broadband passive end model instead of a multi-rigid-body system")
    p.add_argument("--poles", type=integer, default=None,
                   help="with --boundary: number of poles (default: chosen by the fit)")
    p.add_argument("-o", "--output", required=True,
                   help="JSON file for the fitted system (with --boundary: .json or .mat for the state space, "
                        ".csv, .bdf (Nastran), .inp (Abaqus) for its M, C, K)")
    p.add_argument("--mck", action="store_true",
                   help="with --boundary: write the end's M, C, K (second-order form) also as .json or .mat")
    _label_arguments(p)
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=cmd_fit)


def _label_arguments(p) -> None:
    """``--node`` and ``--first-label``: the labels of a .bdf or .inp end file."""
    p.add_argument("--node", type=integer, default=None,
                   help=".bdf/.inp: the grid or node of your model's end that carries the ports (default 1)")
    p.add_argument("--first-label", type=integer, default=None,
                   help=".bdf/.inp: the scalar point or node of the first internal DOF (default 9000001)")


def _export_parser(sub) -> None:
    """The ``export`` command and its arguments, on the subparsers ``sub``."""
    p = sub.add_parser("export", help="export a fitted system or boundary in another format",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="examples:\n  semitrack export system.json --format mat -o system.mat\n"
                              "  semitrack export boundary.json --format mat\n"
                              "  semitrack export boundary.json -o end.bdf      # its M, C, K for Nastran")
    p.add_argument("system", help="system or boundary file written by 'semitrack fit' (.json, .mat, .csv)")
    p.add_argument("--format", choices=END_FORMATS,
                   help="format (default: from the suffix of -o): json, mat (a boundary's state space, or a system); "
                        "csv, bdf (Nastran DMIG), inp (Abaqus *MATRIX INPUT): M, C, K")
    p.add_argument("--mck", action="store_true", help="a boundary's M, C, K (second-order form) also as .json or .mat")
    _label_arguments(p)
    p.add_argument("-o", "--output", default=None,
                   help="file to write (default: the input's name with the format's suffix)")
    p.set_defaults(func=cmd_export)


def _features_parser(sub) -> None:
    """The ``features`` command and its arguments, on the subparsers ``sub``."""
    p = sub.add_parser("features", help="characteristic frequencies (peaks and dips) as a table",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="example:\n  semitrack features slab.toml --fmax 1500")
    _track_and_grid_arguments(p, "search grid step")
    p.add_argument("--csv", action="store_true", help="print CSV instead of a table")
    p.set_defaults(func=cmd_features)


# --- semitrack run -------------------------------------------------------------------------------
#: The routes ``semitrack run --route`` takes by name (``auto`` picks one, :func:`choose_route`).
RUN_ROUTES = ("auto", "window", "fe", "convolution", "moving-green")


def choose_route(track: Track, gaps: dict, speed: float, profile: bool) -> tuple[str, str]:
    """The route ``--route auto`` runs, and why (a sentence for the progress line and the CSV header).

    A flexible slab: the FE model that holds the path (no exact infinite track holds the slab).
    Standing wheels (speed 0) without gaps or a profile: the exact infinite track by convolution,
    which truncates nothing. Otherwise the window that travels with the vehicle: any changes,
    gaps and profile, at the cost of a model of the window's size per step.
    """
    if track.has_flexible_slab:
        return "fe", "a flexible slab: the FE model that holds the path"
    if speed == 0 and not gaps and not profile:
        return "convolution", "standing wheels: the exact infinite track by convolution, nothing truncated"
    held = "rolling wheels" if speed > 0 else "standing wheels over a gap or a profile"
    return "window", f"{held}: the FE window that travels with the vehicle over the exact infinite track"


def _vehicle(path: str):
    from .model.vehiclefile import load_vehicle_toml

    return _description(load_vehicle_toml, path, "vehicle")


def _track_with_changes(path: str):
    from .model.trackfile import load_track_file

    return _description(load_track_file, path, "track")


def _run_inputs(args: argparse.Namespace):
    """Roughness or profile from ``--roughness``, and the files it reads."""
    from .model.roughness import ISO3095_ROUGHNESS_LIMIT, roughness_from_spectrum
    from .model.seriesfile import load_rail_profile, load_roughness_spectrum, series_kind

    if args.roughness is None:
        return None, None, ()
    if args.roughness == "iso3095":
        spectrum = None
    else:
        checked(check_input_path, args.roughness, "--roughness")
        try:
            kind = series_kind(args.roughness)
            if kind == "profile":
                return None, load_rail_profile(args.roughness), (("roughness file", args.roughness),)
            spectrum = load_roughness_spectrum(args.roughness)
        except OSError as err:
            raise InputError(f"--roughness {args.roughness!r}: not iso3095, and the file cannot be read "
                             f"({err.strerror or err}); give iso3095, a spectrum file (wavelength_m, level_dB) or a "
                             "profile file (x_m, r_m)") from None
        except BadInput as err:
            raise InputError(f"--roughness: {err}") from None
    if args.speed == 0:
        raise InputError("--roughness: a spectrum passes the wheels at a speed: give --speed > 0 (with --route "
                         "convolution the wheels stand while it passes), or a rail profile file (x_m, r_m)")
    wavelengths, levels = (None, None) if spectrum is None else spectrum
    longest = max(ISO3095_ROUGHNESS_LIMIT) if wavelengths is None else float(np.max(wavelengths))
    # lines 1 / period apart: at least two in the band of the longest wavelength (its width 0.23 f)
    width = args.speed / longest * (10**0.05 - 10**-0.05) if longest > 0 else 1.0
    period = max(args.duration, 0.1, 2.0 / width)
    try:
        rough = roughness_from_spectrum(args.speed, wavelengths, levels, period=period, seed=args.seed, dt=args.dt)
    except BadInput as err:  # its period is the run's length: the option that sets it is --duration
        raise InputError(f"--roughness over --duration {args.duration!r} s at --speed {args.speed!r} m/s: {err}") \
            from None
    files = () if spectrum is None else (("roughness file", args.roughness),)
    return rough, None, files


def _column(name: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")


def run_csv(res, header: list[str]) -> str:
    """The CSV of ``semitrack run``: ``#`` lines of conventions and summary, then a row per step."""
    k = res.force.reshape(res.t.size, -1).shape[1]
    names = [_column(n) for n in res.vehicle.wheel_names]
    columns, data = ["t_s"], [res.t]
    for j, name in enumerate(names):
        for field, unit in (("x", "m"), ("force", "N"), ("w_wheel", "m"), ("w_rail", "m"), ("roughness", "m")):
            columns.append(f"{name}_{field}_{unit}")
            data.append(getattr(res, field).reshape(res.t.size, k)[:, j])
    if res.track_forces is not None:
        for j, s in enumerate(res.track_forces.supports):
            columns.append(f"support_{s}_rail_seat_N")
            data.append(res.track_forces.rail_seat[:, j])
            if res.track_forces.ballast is not None:
                columns.append(f"support_{s}_ballast_N")
                data.append(res.track_forces.ballast[:, j])
    if res.gaps is not None:
        for j, s in enumerate(res.gaps.supports):
            columns.append(f"hanging_sleeper_{s}_ballast_N")
            data.append(res.gaps.force[:, j])
    buf = io.StringIO()
    buf.writelines(f"# {printable(line)}\n" for line in header)
    buf.write(",".join(columns) + "\n")
    np.savetxt(buf, np.column_stack(data) + 0.0, fmt="%.9g", delimiter=",")  # + 0.0: no "-0" in the file
    return buf.getvalue()


def _summary_lines(res) -> list[str]:
    table = res.summary()
    lines = []
    for item in dict.fromkeys(table.index.get_level_values("item")):
        rows = table.loc[item, "value"]
        lines.append(f"{item}: " + "; ".join(f"{q} {v:.4g}" for q, v in rows.items()))
    return lines


def _run_route(route: str, args: argparse.Namespace, track: Track, local, vehicle, rough, profile, watch: list):
    """The run by the route's entry, with the command's options."""
    from .fe.window import WindowTrack
    from .interaction.fe_model import wheel_rail_response
    from .interaction.infinite_convolution import convolution_response
    from .interaction.moving_green import moving_green_response
    from .methods.infinite import InfiniteTrack

    common = dict(x=args.x, speed=args.speed, dt=args.dt, duration=args.duration, ramp=args.ramp)
    if route == "convolution":
        return convolution_response(InfiniteTrack(track, local.changes), vehicle, rough, **common)
    if route == "moving-green":
        return moving_green_response(track, vehicle, rough, profile=profile, **common)
    if route == "window":
        model = WindowTrack(track, local.changes)
    else:
        reach = max(abs(args.x), abs(args.x + args.speed * args.duration)) + float(np.ptp(vehicle.offsets))
        model = _fe_model(track, local.changes, reach)
    return wheel_rail_response(model, vehicle, rough, profile=profile, watch_supports=watch,
                               ballast_gaps=local.gaps or None, **common)


def cmd_run(args: argparse.Namespace) -> int:
    from .base.checks import check_nonnegative, check_rolling_speed, check_steps, check_time_step

    track, local = _track_with_changes(args.track)
    vehicle = _vehicle(args.vehicle)
    checked(check_nonnegative, "--speed", args.speed)
    if args.speed != 0:
        checked(check_rolling_speed, "--speed", args.speed)
    checked(check_positive, "--duration", args.duration)
    checked(check_positive, "--ramp", args.ramp)
    # the steps counted (and bounded) before the roughness is sampled at dt (its aliasing warning)
    checked(check_steps, args.dt, args.duration, ("--dt", "--duration"))
    if not args.duration > args.ramp:
        raise InputError(f"--duration must exceed --ramp, the roughness's fade-in ({args.ramp!r} s), got "
                         f"{args.duration!r} s")
    checked(check_time_step, "--dt", args.dt)
    checked(check_int_at_least, "--seed", args.seed, 0)
    watch = list(args.watch or ())
    for k in watch:
        checked(check_int_at_least, "--watch", k, -10**9)
    rough, profile, rough_files = _run_inputs(args)
    out, plot = output_paths(("-o", args.output), ("--plot", args.plot),
                             inputs=input_files(args.track, track) + (("vehicle file", args.vehicle),) + rough_files)
    if plot is not None:
        plot_format(plot)
    route, why = choose_route(track, local.gaps, args.speed, profile is not None)
    if args.route != "auto":
        route, why = args.route, "asked for by --route"
    refused = {"convolution": [("gaps", local.gaps), ("a rail profile", profile), ("--watch", watch)],
               "moving-green": [("[[changes]]", local.changes), ("gaps", local.gaps), ("--watch", watch)]}
    given = [name for name, value in refused.get(route, ()) if value]
    if given:
        raise InputError(f"--route {route} takes no {' and no '.join(given)}: give --route window (or auto)")
    if route == "moving-green" and args.speed == 0:
        raise InputError("--route moving-green rolls the wheels: give --speed > 0, or --route convolution")
    progress = Progress("run", 2, quiet=args.quiet)
    progress.update(0, f"route {route}: {why}")
    res = _run_route(route, args, track, local, vehicle, rough, profile, watch)
    progress.update(1)
    progress.close()
    header = [f"semitrack run: route {route} ({why}); {res.elapsed:.3g} s of time integration",
              f"track {track.name!r} ({track_kind(track)}), {len(local.changes)} changed support(s), "
              f"{len(local.gaps)} gap(s); vehicle file {Path(args.vehicle).name!r} ({type(vehicle).__name__}, "
              f"{len(vehicle.wheels)} wheel(s)) from "
              f"x = {args.x:g} m",
              f"speed {args.speed:g} m/s, dt {args.dt:g} s, duration {args.duration:g} s, roughness "
              f"{args.roughness or 'none'}",
              "conventions: SI units; t in s; x along the track from the central mid-span (support k at "
              "x = (k + 1/2) d); displacements downward positive (m); forces compression positive (N); roughness "
              f"the rail surface's drop (m), faded in over the first {res.ramp:g} s",
              "summary (from the end of the fade-in):", *_summary_lines(res)]
    text = run_csv(res, header)
    atomic_write(out, lambda fh: fh.write(text), binary=False)
    if plot is not None:
        from .plotting.contact import run_figure

        fig, _ = run_figure(res, title=f"{track.name}, {route}, {args.speed:g} m/s")
        atomic_write(plot, lambda fh: fig.savefig(fh, format=plot_format(plot), dpi=110), binary=True)
    for line in _summary_lines(res):
        print(line)
    print(f"written to {out}" + (f" and {plot}" if plot is not None else ""))
    return 0


def _fe_model(track: Track, changes: dict, reach: float):
    """The FE model that holds a path ``reach`` m either side of x = 0, with 10 bays beyond and broadband ends."""
    from .boundary.fitting import fit_boundary
    from .fe.ends import BoundaryEnd
    from .fe.models import TruncatedTrack

    n = int(np.ceil(reach / track.spacing)) + 10
    if track.has_flexible_slab:  # whole slabs: the bays each side a multiple of a slab's fasteners
        n = int(np.ceil(n / track.slab.fasteners)) * track.slab.fasteners
    checked(check_work, n, 2000, f"the path asks {n} bays each side", "run the window (--route window)")
    return TruncatedTrack(track, n, BoundaryEnd(boundary=fit_boundary(track)), changes=changes)


def _run_parser(sub) -> None:
    """The ``run`` command and its arguments, on the subparsers ``sub``."""
    p = sub.add_parser("run", help="run a vehicle along a track (with its changes) in time; forces to CSV",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="example:\n  semitrack example bogie > bogie.toml\n"
                              "  semitrack run ballasted.toml bogie.toml --roughness iso3095 --speed 20 "
                              "--duration 0.1 -o run.csv --plot run.png")
    p.add_argument("track", help="track file (TOML), with its [[changes]] if any")
    p.add_argument("vehicle", help="vehicle file (TOML): a wheel, wheels or a bogie ('semitrack example bogie')")
    p.add_argument("--roughness", default=None,
                   help="iso3095 (the standard's limit spectrum), a spectrum file (wavelength_m, level_dB) or a rail "
                        "profile file (x_m, r_m); default: a smooth rail")
    p.add_argument("--speed", type=number, required=True, help="the vehicle's speed, m/s (0: standing wheels)")
    p.add_argument("--duration", type=number, default=0.1, help="the run's length, s (default 0.1)")
    p.add_argument("--dt", type=number, default=2e-5, help="time step, s (default 2e-5)")
    p.add_argument("--ramp", type=number, default=0.02, help="the roughness's fade-in, s (default 0.02)")
    p.add_argument("--x", type=number, default=0.0, help="where the first wheel starts, m (default 0, a mid-span)")
    p.add_argument("--route", choices=RUN_ROUTES, default="auto",
                   help="auto (default: the window for rolling wheels, the convolution for standing ones, the FE "
                        "model on a flexible slab), or one by name")
    p.add_argument("--watch", type=integer, nargs="+", metavar="K", help="supports whose rail-seat and ballast "
                                                                          "forces to record (window and fe routes)")
    p.add_argument("--seed", type=integer, default=0, help="seed of the roughness's random phases (default 0)")
    p.add_argument("-o", "--output", required=True, help="CSV file to write")
    p.add_argument("--plot", help="also write a plot; its suffix gives the format: "
                                  f"{', '.join('.' + f for f in PLOT_FORMATS)}")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=cmd_run)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="semitrack", description=(
        "Receptance of a semi-infinite periodic railway track and its equivalent multi-rigid-body "
        "system. Track files are TOML; 'semitrack example slab > slab.toml' writes one to start from."),
        epilog="Exit codes: 0 success, 2 bad input, 1 unexpected failure, 130 interrupted, 143 terminated. "
               "'semitrack COMMAND --help' shows an example of each command.")
    parser.add_argument("--version", action="version", version=f"semitrack {__version__}")
    sub = parser.add_subparsers(dest="command", title="commands", metavar="COMMAND", parser_class=_Parser)
    for add in (_example_parser, _receptance_parser, _decay_parser, _fit_parser, _export_parser, _features_parser,
                _run_parser):
        add(sub)
    return parser


def _error(command: str, message: str) -> None:
    print(f"{command}: error: {printable(message)}", file=sys.stderr)


def _warning(command: str, message, category, filename, lineno, file=None, line=None) -> None:
    """A warning on one line of stderr (``warnings.showwarning``'s signature), like the errors."""
    print(f"{command}: warning: {printable(str(message))}", file=sys.stderr)


def _silence_stdout() -> None:
    """Point stdout at /dev/null after its reader went away, so that the flush at exit is quiet."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


def run(args: argparse.Namespace) -> int:
    """Run the parsed command; bad input and failures become exit codes and one-line messages.

    Parameters
    ----------
    args : argparse.Namespace
        From :func:`build_parser`.

    Returns
    -------
    int
        0 success, 2 bad input (one line on stderr); an unexpected failure propagates.
    """
    command = f"semitrack {args.command}"
    with warnings.catch_warnings():
        warnings.showwarning = functools.partial(_warning, command)
        try:
            with silenced() if getattr(args, "quiet", False) else contextlib.nullcontext():  # the package's bars too
                code = args.func(args)
            if sys.stdout is not None:
                emit("")  # flushes what print() left in the buffer: a full disk is reported now, not at exit
            return code
        except BrokenPipeError:  # the reader of stdout went away (e.g. `| head`): not a failure
            _silence_stdout()
            return 0
        except BadInput as err:  # InputError, or a refusal by the package
            _error(command, str(err))
        except OSError as err:  # an input or output file: unreadable, unwritable, disk full, ...
            _error(command, f"{err.filename}: {err.strerror}" if err.filename else str(err))
    return 2


@contextlib.contextmanager
def _termination_as_exception():
    """SIGTERM raises :class:`Terminated` in the main thread while the program runs (then restored)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def terminate(signum, frame):
        raise Terminated

    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the program.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit code: 0 success, 2 bad input, 1 unexpected failure, 130 interrupted (SIGINT),
        143 terminated (SIGTERM).
    """
    command = "semitrack"
    try:
        with _termination_as_exception():
            parser = build_parser()
            try:
                args = parser.parse_args(argv)
            except SystemExit as stop:  # --help, --version, usage errors
                return int(stop.code or 0)
            if args.command is None:  # a usage error: show what there is to run
                parser.print_help(sys.stderr)
                return 2
            command = f"semitrack {args.command}"
            try:
                return run(args)
            except Exception as err:  # noqa: BLE001 - an unexpected failure is reported in full
                if caused_by_interrupt(err):  # e.g. Ctrl-C during a deferred import of numpy or scipy
                    raise KeyboardInterrupt from None
                print(f"{command}: unexpected failure, please report it:", file=sys.stderr)
                traceback.print_exc()
                return 1
    except KeyboardInterrupt:
        print(f"{command}: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print(f"{command}: terminated", file=sys.stderr)
        return 143
