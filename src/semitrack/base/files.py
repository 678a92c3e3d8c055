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

import os
import secrets
import stat
from collections.abc import Callable
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
