"""The ``semitrack`` command-line program: receptance, fit, export, features.

Exit codes: 0 success, 2 bad input (a one-line message on stderr, no traceback), 1 unexpected
failure (with a traceback, so that it can be reported). Results go to files written atomically
or to stdout; progress goes to stderr, and only when stderr is a terminal.
"""

from __future__ import annotations

import argparse
import io
import os
import sys
import traceback
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from . import __version__
from .base.checks import check_band, check_int_at_least, check_positive
from .base.conventions import ALL_ELEMENTS, ELEMENT_TEX, ELEMENT_UNITS, ELEMENTS
from .base.paper_values import FIT_BANDS, PAPER_GRID_BAND, PAPER_GRID_STEP
from .equivalent.io import atomic_write, export_system, load_system_json, save_system_json
from .model.trackfile import TrackFileError, load_track_toml
from .model.tracks import Track
from .progress import Progress

#: Largest frequency grid the CLI accepts (a guard against a mistyped --df).
MAX_FREQUENCIES = 200_000
BLOCK = 50  # frequencies per progress step


class InputError(ValueError):
    """Bad input from the command line or an input file: reported with exit code 2."""


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error message (exit code 2 as usual)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


# ------------------------------------------------------------------------------------------
def checked(check: Callable, *args):
    """Run one of the package's checks (:mod:`semitrack.base.checks`); its error becomes an InputError."""
    try:
        return check(*args)
    except (TypeError, ValueError) as err:
        raise InputError(str(err)) from None


def frequency_grid(fmin: float, fmax: float, df: float) -> np.ndarray:
    """The grid fmin, fmin + df, ... up to fmax inclusive (Hz); checks the three numbers."""
    fmin, fmax, df = (checked(check_positive, name, value) for name, value in
                      (("--fmin", fmin), ("--fmax", fmax), ("--df", df)))
    if fmin > fmax:
        raise InputError(f"--fmin must not exceed --fmax, got fmin={fmin!r} > fmax={fmax!r}")
    n = int(np.floor((fmax - fmin) / df + 1e-9)) + 1
    if n > MAX_FREQUENCIES:
        raise InputError(f"the grid would hold {n} frequencies (more than {MAX_FREQUENCIES}); increase --df")
    return fmin + df * np.arange(n)


def _track(path: str) -> Track:
    try:
        return load_track_toml(path)
    except TrackFileError as err:
        raise InputError(str(err)) from None


def _output_path(path: str) -> Path:
    out = Path(path)
    if not out.parent.exists():
        raise InputError(f"output folder {str(out.parent)!r} does not exist")
    return out


# ------------------------------------------------------------------------------------------
def receptance_csv(track: Track, f: np.ndarray, alpha: np.ndarray, method: str) -> str:
    """CSV text of a receptance sweep: header comments with units and signs, then one row per f.

    The columns are ``f_Hz`` and, for each element of
    :data:`semitrack.base.conventions.ALL_ELEMENTS`, its real part, imaginary part, magnitude and
    phase (``alpha11_re``, ``alpha11_im``, ``alpha11_abs``, ``alpha11_phase``, ...).
    """
    buf = io.StringIO()
    buf.write(f"# semitrack {__version__}: receptance at the end of the semi-infinite track "
              f"'{track.name}' (method={method})\n")
    units = ", ".join(f"{name} in {ELEMENT_UNITS[name]}" for name in ALL_ELEMENTS)
    buf.write(f"# units: f in Hz; {units} (1/N = m/(N m) = rad/N); phase in rad\n")
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


def _plot_receptance(path: Path, track: Track, f: np.ndarray, alpha: np.ndarray) -> None:
    from matplotlib.figure import Figure  # no pyplot: the CLI selects no backend

    fig = Figure(figsize=(10, 3.4), layout="constrained")
    axes = fig.subplots(1, len(ELEMENTS))
    for ax, (name, (i, k)) in zip(axes, ELEMENTS.items()):
        ax.semilogy(f, np.abs(alpha[:, i, k]), "k-", lw=1.2)
        ax.set_xlabel("Frequency (Hz)")
        ax.set_ylabel(f"|{ELEMENT_TEX[name]}| ({ELEMENT_UNITS[name]})")
        ax.grid(alpha=0.3)
    fig.suptitle(f"Semi-infinite track '{track.name}': end receptance")
    atomic_write(path, lambda fh: fig.savefig(fh, format="png", dpi=110), binary=True)


def cmd_receptance(args: argparse.Namespace) -> int:
    from .methods.receptance import semi_infinite_receptance

    track = _track(args.track)
    f = frequency_grid(args.fmin, args.fmax, args.df)
    out = None if args.output == "-" else _output_path(args.output)
    plot = _output_path(args.plot) if args.plot else None
    progress = Progress("receptance", int(np.ceil(f.size / BLOCK)), quiet=args.quiet)
    blocks = []
    for n, start in enumerate(range(0, f.size, BLOCK), start=1):
        blocks.append(semi_infinite_receptance(track, f[start : start + BLOCK], method=args.method))
        progress.update(n)
    progress.close()
    alpha = np.concatenate(blocks)
    text = receptance_csv(track, f, alpha, args.method)
    if out is None:
        sys.stdout.write(text)
    else:
        atomic_write(out, lambda fh: fh.write(text), binary=False)
    if plot is not None:
        _plot_receptance(plot, track, f, alpha)
    return 0


def cmd_fit(args: argparse.Namespace) -> int:
    track = _track(args.track)
    fmin, fmax = checked(check_band, args.band, "--band")
    checked(check_int_at_least, "--seed", args.seed, 0)
    out = _output_path(args.output)
    if args.boundary:
        return _fit_boundary(args, track, (fmin, fmax), out)
    from .equivalent.fitting import fit_equivalent

    checked(check_int_at_least, "--bars", args.bars, 1)
    layout = "ballasted" if track.is_ballasted else "slab"
    progress = Progress("fit", 1, quiet=args.quiet)
    progress.update(0, f"fitting N = {args.bars} bars, {layout} layout")
    fit = fit_equivalent(track, layout=layout, n_bars=args.bars, band=(fmin, fmax), seed=args.seed,
                         constrained=not args.unconstrained)
    progress.update(1)
    progress.close()
    save_system_json(fit.system, out)
    print(f"fitted a {layout} equivalent system with {args.bars} bars to '{track.name}' over {fmin:g}-{fmax:g} Hz")
    print(f"median relative error {fit.median_error:.4f}, maximum {fit.max_error:.4f} ({', '.join(ELEMENTS)})")
    print(f"written to {out}")
    return 0


def _fit_boundary(args: argparse.Namespace, track: Track, band: tuple[float, float], out: Path) -> int:
    """``semitrack fit --boundary``: the broadband passive end model, written as JSON or .mat."""
    from .boundary.fitting import check_n_poles, fit_boundary
    from .boundary.io import save_boundary

    if out.suffix.lower() not in (".json", ".mat"):
        raise InputError(f"-o must name a .json or .mat file for --boundary, got {out.name!r}")
    if args.poles is not None:
        checked(check_n_poles, args.poles, "--poles")
    progress = Progress("fit", 1, quiet=args.quiet)
    progress.update(0, "fitting a broadband boundary")
    bnd = fit_boundary(track, band=band, n_poles=args.poles, seed=args.seed)
    progress.update(1)
    progress.close()
    save_boundary(bnd, out)
    proof = "proven passive" if bnd.passivity else "NOT passive"
    print(f"fitted a broadband boundary with {bnd.n_poles} poles to '{track.name}' over {band[0]:g}-{band[1]:g} Hz "
          f"({proof})")
    print(f"median relative error {bnd.median_error:.4f}, maximum {bnd.max_error:.4f} ({', '.join(ELEMENTS)})")
    print(f"written to {out}")
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    try:
        system = load_system_json(args.system)
    except (OSError, ValueError, TypeError, KeyError) as err:
        raise InputError(f"{args.system}: cannot load the system: {err}") from None
    out = _output_path(args.output)
    if args.format is None and out.suffix.lower() not in (".json", ".csv", ".mat"):
        raise InputError(f"cannot tell the format from {out.name!r}: give --format json|csv|mat or a "
                         ".json/.csv/.mat file name")
    export_system(system, out, format=args.format)
    print(f"{args.format or out.suffix.lstrip('.')} export of a {system.layout} system with "
          f"{system.n_dof} DOFs written to {out}")
    return 0


def cmd_features(args: argparse.Namespace) -> int:
    from .methods.features import characteristic_frequencies

    track = _track(args.track)
    f = frequency_grid(args.fmin, args.fmax, args.df)
    if f.size < 3:
        raise InputError("the frequency grid needs at least 3 points to find peaks and dips")
    table = characteristic_frequencies(track, band=(f[0], f[-1]), df=args.df)
    table = table.rename(columns={"f": "f (Hz)", "f_grid": "grid f (Hz)"})
    if args.csv:
        sys.stdout.write(table.to_csv(index=False, float_format="%.6g"))
    else:
        print(f"peaks and dips of '{track.name}' between {f[0]:g} and {f[-1]:g} Hz (exact method, refined):")
        print(table.to_string(index=False, float_format=lambda v: f"{v:.6g}"))
    return 0


# ------------------------------------------------------------------------------------------
def _track_and_grid_arguments(p: argparse.ArgumentParser, step: str) -> None:
    p.add_argument("track", help="track description file (TOML)")
    (fmin, fmax), df = PAPER_GRID_BAND, PAPER_GRID_STEP  # the paper's grid by default
    p.add_argument("--fmin", type=float, default=fmin, help=f"lowest frequency, Hz (default {fmin:g})")
    p.add_argument("--fmax", type=float, default=fmax, help=f"highest frequency, Hz (default {fmax:g})")
    p.add_argument("--df", type=float, default=df, help=f"{step}, Hz (default {df:g})")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="semitrack", description=(
        "Receptance of a semi-infinite periodic railway track and its equivalent multi-rigid-body "
        "system. Track files are TOML; see the examples shipped in semitrack/examples."),
        epilog="Exit codes: 0 success, 2 bad input, 1 unexpected failure.")
    parser.add_argument("--version", action="version", version=f"semitrack {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("receptance", help="receptance of the semi-infinite track to CSV",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="example:\n  semitrack receptance slab.toml --fmin 3 --fmax 3000 --df 6 -o alpha.csv "
                              "--plot alpha.png")
    _track_and_grid_arguments(p, "frequency step")
    p.add_argument("--method", choices=("transfer", "wavenumber"), default="transfer",
                   help="transfer: exact (default); wavenumber: the paper's method and settings")
    p.add_argument("-o", "--output", default="-", help="CSV file to write (default: stdout)")
    p.add_argument("--plot", help="also write a PNG plot of the magnitudes")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=cmd_receptance)

    p = sub.add_parser("fit", help="fit an equivalent multi-rigid-body system or a broadband boundary",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="examples:\n  semitrack fit ballasted.toml --bars 5 --band {:g} {:g} --seed 0 "
                              "-o system.json\n"
                              "  semitrack fit slab.toml --boundary --band 3 3000 -o boundary.json"
                              .format(*FIT_BANDS["ballasted"]))
    p.add_argument("track", help="track description file (TOML)")
    p.add_argument("--bars", type=int, default=5, help="number of rigid bars N (default 5)")
    p.add_argument("--band", type=float, nargs=2, metavar=("FMIN", "FMAX"), required=True, help="band to fit, Hz")
    p.add_argument("--seed", type=int, default=0, help="seed of the multi-start (default 0)")
    p.add_argument("--unconstrained", action="store_true", help="drop the paper's frequency constraints")
    p.add_argument("--boundary", action="store_true",
                   help="fit the broadband passive end model instead of a multi-rigid-body system")
    p.add_argument("--poles", type=int, default=None,
                   help="with --boundary: number of poles (default: chosen by the fit)")
    p.add_argument("-o", "--output", required=True,
                   help="JSON file for the fitted system (with --boundary: .json or .mat)")
    p.add_argument("--quiet", action="store_true", help="no progress line")
    p.set_defaults(func=cmd_fit)

    p = sub.add_parser("export", help="export M, C, K of a fitted system",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="example:\n  semitrack export system.json --format mat -o system.mat")
    p.add_argument("system", help="system file written by 'semitrack fit' (JSON)")
    p.add_argument("--format", choices=("json", "csv", "mat"), help="format (default: from the suffix of -o)")
    p.add_argument("-o", "--output", required=True, help="file to write")
    p.set_defaults(func=cmd_export)

    p = sub.add_parser("features", help="characteristic frequencies (peaks and dips) as a table",
                       formatter_class=argparse.RawDescriptionHelpFormatter,
                       epilog="example:\n  semitrack features slab.toml --fmax 1500")
    _track_and_grid_arguments(p, "search grid step")
    p.add_argument("--csv", action="store_true", help="print CSV instead of a table")
    p.set_defaults(func=cmd_features)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the program; returns the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:  # --help, --version, usage errors
        return int(stop.code or 0)
    try:
        return args.func(args)
    except InputError as err:
        print(f"semitrack {args.command}: error: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader of stdout went away (e.g. `| head`): not a failure
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - silences the flush at exit
        return 0
    except KeyboardInterrupt:
        print(f"semitrack {args.command}: interrupted", file=sys.stderr)
        return 1
    except Exception:  # noqa: BLE001 - an unexpected failure is reported in full
        print(f"semitrack {args.command}: unexpected failure, please report it:", file=sys.stderr)
        traceback.print_exc()
        return 1
