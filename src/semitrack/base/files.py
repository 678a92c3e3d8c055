"""Files the package writes and reads: output paths checked before the work, atomic writes, bounded reads.

Every file the package or its command line writes goes through :func:`atomic_write`: the content
goes to a hidden temporary file next to the target, which then replaces the target in one
:func:`os.replace`. A reader (or a second writer) therefore sees the old file or the new one,
never a mix; an error, a full disk, Ctrl-C or a SIGTERM turned into an exception (as the command
line does) leaves the old file intact and removes the temporary one.

What an output path may name (:func:`check_output_path`, also run by :func:`atomic_write`): a
regular file or nothing yet, in an existing, writable folder. A symbolic link is followed and its
target written (the link stays a link); a directory, FIFO, device or socket is refused, never
replaced by a regular file. New files get the mode ``0o666`` less the umask, like any file the
user creates; a replaced file keeps its mode.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import secrets
import stat
import struct
import zlib
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

from .errors import InputError, InputTypeError

#: Kinds of file an output path must not name, by :mod:`stat` test: they are not ours to replace.
_NOT_REGULAR = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                (stat.S_ISSOCK, "a socket"))


def _as_path(path: object, name: str) -> Path:
    text = os.fspath(path) if isinstance(path, (str, os.PathLike)) else None
    if not isinstance(text, str):
        raise InputTypeError(f"{name} must be a str or os.PathLike (of str), got {type(path).__name__}")
    if text == "" or "\x00" in text:
        raise InputError(f"{name} must name a file, got {text!r}")
    return Path(text)


def check_output_path(path: str | os.PathLike, name: str = "path") -> Path:
    """Check, before any work, that ``path`` can be written; return the file that will be written.

    Parameters
    ----------
    path : str or os.PathLike
        The output file as the user named it.
    name : str
        How messages call it (e.g. ``"-o"``).

    Returns
    -------
    Path
        The file to write: ``path`` itself, or the final target of a symbolic link (a dangling
        link's target need not exist yet).

    Raises
    ------
    TypeError
        If ``path`` is not a str or path.
    ValueError
        If it is empty, names a directory, FIFO, device or socket, a symbolic-link loop, a
        read-only file, or a folder that does not exist or cannot be written. The message names
        ``name``, the path and the rule.

    Examples
    --------
    >>> check_output_path("/dev/null", "-o")
    Traceback (most recent call last):
    ...
    semitrack.base.errors.InputError: -o '/dev/null' is a character device: name a regular file to write
    """
    given = _as_path(path, name)
    target = Path(os.path.realpath(given)) if given.is_symlink() else given
    if target.is_symlink():  # realpath stops at a loop
        raise InputError(f"{name} {str(given)!r} is a loop of symbolic links: name a regular file to write")
    try:
        mode = target.stat().st_mode
    except FileNotFoundError:
        mode = None
    except OSError as err:  # e.g. ENOTDIR: a path component is a file
        raise InputError(f"{name} {str(given)!r} cannot be written ({err.strerror})") from None
    for is_kind, kind in _NOT_REGULAR:
        if mode is not None and is_kind(mode):
            raise InputError(f"{name} {str(given)!r} is {kind}: name a regular file to write")
    folder = target.parent
    if not folder.is_dir():
        raise InputError(f"{name} {str(given)!r}: the folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{name} {str(given)!r}: the folder {str(folder)!r} is not writable")
    if mode is not None and not os.access(target, os.W_OK):
        raise InputError(f"{name} {str(given)!r} is read-only: make it writable or name another file")
    return target


def _create_temporary(target: Path) -> tuple[int, Path]:
    """A new hidden file next to ``target``, created with mode 0o666 so that the umask applies.

    (:func:`tempfile.mkstemp` would create it 0600, private whatever the user's umask.)
    """
    while True:
        tmp = target.with_name(f".{target.name}.{secrets.token_hex(4)}.tmp")
        try:
            return os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666), tmp
        except FileExistsError:
            continue


def atomic_write(path: str | os.PathLike, write: Callable[[IO], Any], binary: bool = False) -> Path:
    """Call ``write(fh)`` on a temporary file next to ``path``'s target, then move it onto the target.

    Parameters
    ----------
    path : str or os.PathLike
        The file to (re)place, checked by :func:`check_output_path` (a symbolic link is written
        through to its target).
    write : callable
        Writes the content to the open file object it is given.
    binary : bool
        Open the temporary file in binary mode (else text, UTF-8, no newline translation).

    Returns
    -------
    Path
        ``path`` as given.

    Raises
    ------
    ValueError
        From :func:`check_output_path`.
    OSError
        When the file cannot be written (e.g. the disk is full); its ``filename`` is ``path``.
        On any error or interruption the temporary file is removed and the target is left as it was.
    """
    target = check_output_path(path)
    tmp = None
    try:
        fd, tmp = _create_temporary(target)
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"encoding": "utf-8", "newline": ""})) as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        if target.exists():  # a replaced file keeps its mode; a new one has 0o666 less the umask
            os.chmod(tmp, stat.S_IMODE(target.stat().st_mode))
        os.replace(tmp, target)
        tmp = None
    except OSError as err:
        raise OSError(err.errno, f"cannot write the file ({err.strerror or err})", os.fspath(path)) from err
    finally:
        if tmp is not None:
            tmp.unlink(missing_ok=True)
    return Path(path)


@contextlib.contextmanager
def exclusive(path: str | os.PathLike) -> Iterator[None]:
    """Hold ``path``'s lock file (``<path>.lock``) while the block runs: one process at a time.

    For results computed once per cache folder by several processes at once (two chapters of the
    book executed together): the second waits while the first computes and stores the result,
    then reads it, instead of computing it again. The lock is the operating system's
    (:func:`fcntl.flock`, released when the block ends or the process dies); where there is none
    (Windows) the block runs unlocked, and the atomic write still keeps the file whole.

    Parameters
    ----------
    path : str or os.PathLike
        The file the block computes; its folder must exist.

    Yields
    ------
    None
    """
    try:
        import fcntl
    except ImportError:  # no POSIX locks here: the atomic write alone
        yield
        return
    with open(f"{os.fspath(path)}.lock", "a", encoding="utf-8") as handle:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle.fileno(), fcntl.LOCK_UN)


def read_text(path: str | os.PathLike, max_bytes: int, what: str = "file") -> str:
    """The UTF-8 text of an input file, refusing one larger than ``max_bytes`` (e.g. ``/dev/zero``).

    Parameters
    ----------
    path : str or os.PathLike
        The file (a pipe such as ``/dev/stdin`` works too: it is read, not sized).
    max_bytes : int
        Largest content accepted (bytes).
    what : str
        What the file is, for messages (e.g. ``"track file"``).

    Returns
    -------
    str

    Raises
    ------
    OSError
        If it cannot be opened or read.
    ValueError
        If it is larger than ``max_bytes`` or not UTF-8 text (naming the offending byte).
    """
    with open(path, "rb") as fh:
        data = fh.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise InputError(f"{path}: larger than {max_bytes} bytes: not a {what}")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise InputError(f"{path}: not a UTF-8 text {what} (byte 0x{data[err.start]:02x} at offset "
                         f"{err.start})") from None


def read_json(path: str | os.PathLike, max_bytes: int, what: str = "file"):
    """The JSON content of an input file, read as bounded text (:func:`read_text`).

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    max_bytes : int
        Largest content accepted (bytes).
    what : str
        What the file is, for messages (e.g. ``"boundary file"``).

    Returns
    -------
    object
        What :func:`json.loads` returns.

    Raises
    ------
    OSError
        If it cannot be opened or read.
    ValueError
        If it is too large, not UTF-8, not JSON, or nested too deeply for the parser; the message
        names the file.
    """
    text = read_text(path, max_bytes, what)
    try:
        return json.loads(text)
    except RecursionError:
        raise InputError(f"{path}: not a {what}: its objects or arrays are nested too deeply") from None
    except ValueError as err:
        raise InputError(f"{path}: not a JSON file: {err}") from None


#: The first bytes of a MATLAB 5 (and 7, compressed) file, as :func:`scipy.io.savemat` writes it.
_MAT5_HEADER = b"MATLAB 5.0 MAT-file"
_MAT_COMPRESSED = 15  # miCOMPRESSED: a zlib stream holding one variable


def _mat_inflated_size(data: bytes, limit: int, source: str) -> int:
    """Bytes of a MAT-5 file's variables once inflated, refusing past ``limit`` without inflating more."""
    order = "<" if data[126:128] == b"IM" else ">"
    pos, total = 128, 0
    while pos + 8 <= len(data):
        kind, nbytes = struct.unpack(order + "II", data[pos:pos + 8])
        if kind >> 16:  # a small data element (type and size in one word): 8 bytes in all
            kind, nbytes, step = kind & 0xFFFF, kind >> 16, 8
        else:
            step = 8 + nbytes + (-nbytes % 8 if kind != _MAT_COMPRESSED else 0)
        if kind == _MAT_COMPRESSED:
            inflater = zlib.decompressobj()
            try:
                total += len(inflater.decompress(data[pos + 8:pos + 8 + nbytes], limit - total + 1))
            except zlib.error:
                raise InputError(f"{source}: not a readable MAT file (a compressed variable is corrupt)") from None
        else:
            total += nbytes
        if total > limit:
            raise InputError(f"{source}: its variables inflate to more than {limit} bytes: not a file we wrote")
        pos += step
    return total


def read_mat(path: str | os.PathLike, max_bytes: int, what: str = "file", max_inflated: int | None = None,
             simplify: bool = False) -> dict:
    """The variables of a MATLAB 5 ``.mat`` file, sizes bounded before :func:`scipy.io.loadmat` parses it.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    max_bytes : int
        Largest file accepted (bytes).
    what : str
        What the file is, for messages (e.g. ``"boundary file"``).
    max_inflated : int, optional
        Largest total size of the variables once their compression is undone (bytes); default
        ``4 * max_bytes``. A small file whose compressed variable inflates to gigabytes is refused
        after inflating at most this much.
    simplify : bool
        Structs as dicts and cells as lists, squeezed (:func:`scipy.io.loadmat`'s
        ``simplify_cells``); else arrays as stored (``squeeze_me=False``).

    Returns
    -------
    dict
        Variable name -> value, as :func:`scipy.io.loadmat` gives them (its ``__header__``-like
        entries removed).

    Raises
    ------
    OSError
        If it cannot be opened or read.
    ValueError
        If it is empty, too large, not a MATLAB 5 file (JSON, random bytes, a v7.3/HDF5 file),
        truncated or corrupt; one line naming the file.
    """
    with open(path, "rb") as fh:
        data = fh.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise InputError(f"{path}: larger than {max_bytes} bytes: not a {what}")
    if data[:8] == b"\x89HDF\r\n\x1a\n" or data[512:520] == b"\x89HDF\r\n\x1a\n" or data[124:126] == b"\x00\x02":
        raise InputError(f"{path}: a MATLAB v7.3 (HDF5) file: save the {what} with -v7 (format 5)")
    if len(data) < 128 or not data.startswith(_MAT5_HEADER) or data[126:128] not in (b"IM", b"MI"):
        raise InputError(f"{path}: not a MATLAB 5 .mat file ({len(data)} bytes without its header): "
                         f"not a {what}")
    _mat_inflated_size(data, 4 * max_bytes if max_inflated is None else max_inflated, str(path))
    import scipy.io  # here, not at the top: it costs ~0.15 s of every command line's start-up

    try:
        content = scipy.io.loadmat(io.BytesIO(data), squeeze_me=simplify, simplify_cells=simplify)
    except Exception as err:  # scipy's MatReadError, ValueError, IndexError, ... of a damaged file
        raise InputError(f"{path}: not a readable MAT file ({type(err).__name__}: "
                         f"{str(err).splitlines()[0] if str(err) else 'corrupt'})") from None
    return {k: v for k, v in content.items() if not k.startswith("__")}
