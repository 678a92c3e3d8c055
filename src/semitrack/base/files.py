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

from .errors import InputError, InputTypeError, unreadable_file

#: Kinds of file an output path must not name, by :mod:`stat` test: they are not ours to replace.
_NOT_REGULAR = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                (stat.S_ISSOCK, "a socket"))


def _as_path(path: object, name: str, what: str = "a file") -> Path:
    text = os.fspath(path) if isinstance(path, (str, os.PathLike)) else None
    if not isinstance(text, str):
        raise InputTypeError(f"{name} must be a str or os.PathLike (of str), got {type(path).__name__}")
    if text == "" or "\x00" in text:
        raise InputError(f"{name} must name {what}, got {text!r}")
    return Path(text)


def check_input_path(path: object, name: str = "path") -> Path:
    """``path`` as a Path, refused at once (naming ``name``) when it is not a str or path, empty or holds NUL.

    An empty string would otherwise name the current folder (``Path("") == Path(".")``).

    Parameters
    ----------
    path : object
        The file as the user named it.
    name : str
        How messages call it.

    Returns
    -------
    Path
    """
    return _as_path(path, name)


def file_suffix(path: object, format: object = None) -> str:
    """The lower-case suffix a file goes by: ``format`` when given (``"mat"`` or ``".mat"``), else ``path``'s.

    Parameters
    ----------
    path : str or os.PathLike
        The file (checked as :func:`check_input_path` does).
    format : str, optional
        The format named by the caller.

    Returns
    -------
    str
        E.g. ``".json"``; ``""`` for a path without a suffix.
    """
    given = _as_path(path, "path")
    if format is None:
        return given.suffix.lower()
    if not isinstance(format, str):
        raise InputTypeError(f"format must be a str such as 'json' or None, got {type(format).__name__}")
    return f".{format.lower().lstrip('.')}"


def check_output_path(path: str | os.PathLike, name: str = "path", follow_links: bool = True) -> Path:
    """Check, before any work, that ``path`` can be written; return the file that will be written.

    Parameters
    ----------
    path : str or os.PathLike
        The output file as the user named it.
    name : str
        How messages call it (e.g. ``"-o"``).
    follow_links : bool
        A symbolic link at ``path`` is written through to its target (the user's own link, e.g.
        ``-o latest.csv``); False replaces the link itself (a cache file: a link planted in the
        package's cache folder must not make it write a file elsewhere).

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
    _check_name_length(given, given, name)  # before any stat: a name past the limit raises there
    if not follow_links:
        target = given
        mode = None if not os.path.lexists(given) or given.is_symlink() else given.stat().st_mode
        for is_kind, kind in _NOT_REGULAR:
            if mode is not None and is_kind(mode):
                raise InputError(f"{name} {str(given)!r} is {kind}: name a regular file to write")
        if not given.parent.is_dir():
            raise InputError(f"{name} {str(given)!r}: the folder {str(given.parent)!r} does not exist")
        if not os.access(given.parent, os.W_OK | os.X_OK):
            raise InputError(f"{name} {str(given)!r}: the folder {str(given.parent)!r} is not writable")
        _check_name_length(given, target, name)
        return target
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
    _check_name_length(given, target, name)
    return target


#: What :func:`_temporary_name` adds to a file's name: ``.`` before it, ``.<8 hex>.tmp`` after it.
_TEMPORARY_EXTRA = 14


def _check_name_length(given: Path, target: Path, name: str) -> None:
    """Refuse a file name its folder cannot hold with the temporary file's extra characters, and a
    path the system cannot name (a folder's name or the whole path too long): the stat would raise."""
    try:
        limit = os.pathconf(target.parent, "PC_NAME_MAX")
    except (OSError, ValueError):  # the folder does not exist (said next), or no such query: the common limit
        limit = 255
    whole = len(os.fsencode(str(target))) + _TEMPORARY_EXTRA
    longest = max((len(os.fsencode(part)) for part in target.parts[:-1]), default=0)
    if whole > 4096 or longest > limit:  # Linux's PATH_MAX; a folder's name as long as no folder holds
        raise InputError(f"{name} {str(given)[:60]!r}...: the path is {whole - _TEMPORARY_EXTRA} bytes with a "
                         f"folder name of {longest}, more than the system names (4096, {limit}): name a shorter path")
    size = len(os.fsencode(target.name))
    if size + _TEMPORARY_EXTRA > limit:
        raise InputError(f"{name} {str(given)[:60]!r}...: its file name is {size} bytes, more than the "
                         f"{limit - _TEMPORARY_EXTRA} its folder holds (with the temporary file's "
                         f"{_TEMPORARY_EXTRA}): name a shorter file")


def _temporary_name(target: Path) -> Path:
    """A hidden name next to ``target`` for its temporary file (:data:`_TEMPORARY_EXTRA` characters more)."""
    return target.with_name(f".{target.name}.{secrets.token_hex(4)}.tmp")


def _create(tmp: Path) -> int:
    """Create ``tmp`` (new, mode 0o666 less the umask: :func:`tempfile.mkstemp` would make it 0600)."""
    return os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)


def atomic_write(path: str | os.PathLike, write: Callable[[IO], Any], binary: bool = False,
                 follow_links: bool = True) -> Path:
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
    follow_links : bool
        False: a symbolic link at ``path`` is replaced, not written through
        (:func:`check_output_path`).

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
    target = check_output_path(path, follow_links=follow_links)
    tmp = None
    try:
        while True:
            # the name is held before the file exists: a signal between the two cannot leave it behind
            tmp = _temporary_name(target)
            try:
                fd = _create(tmp)
                break
            except FileExistsError:
                continue
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
    lock = f"{os.fspath(path)}.lock"
    if os.path.islink(lock):  # the lock's name is the package's own: a link there is not followed
        os.unlink(lock)
    try:
        fd = os.open(lock, os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0),
                     0o666)
    except OSError as err:  # a link planted meanwhile (ELOOP), a FIFO nobody reads (ENXIO), ...
        raise InputError(f"the cache's lock file {lock!r} cannot be opened ({err.strerror}): remove it") from None
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise InputError(f"the cache's lock file {lock!r} is not a regular file: remove it")
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fd, fcntl.LOCK_UN)
    finally:
        os.close(fd)


def check_cache_folder(folder: str | os.PathLike, name: str = "cache") -> Path:
    """Check, before any work, that ``folder`` can hold the package's cache files; create it.

    Parameters
    ----------
    folder : str or os.PathLike
        The cache folder (created with its parents when absent).
    name : str
        How messages call it (the parameter's name).

    Returns
    -------
    Path

    Raises
    ------
    InputTypeError
        If ``folder`` is not a str or path.
    InputError
        If it is empty, names a file, a dangling link or a loop of links, cannot be created or is
        not writable; the message names ``name`` and the folder. Raised before any result is
        computed, so that none is lost.
    """
    given = _as_path(folder, name, "a folder")
    if os.path.lexists(given) and not given.is_dir():
        kind = "a symbolic link that leads to no folder" if given.is_symlink() else "a file"
        raise InputError(f"{name} {str(given)!r} is {kind}: name a folder for the cache")
    try:
        given.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise InputError(f"{name} {str(given)!r}: the folder cannot be created ({err.strerror})") from None
    if not os.access(given, os.W_OK | os.X_OK):
        raise InputError(f"{name} {str(given)!r}: the folder is not writable: name another one, or None")
    return given


def read_bytes(path: str | os.PathLike, max_bytes: int, what: str = "file") -> bytes:
    """The bytes of an input file, at most ``max_bytes``: every reader of the package reads through it.

    A FIFO is opened without waiting for a writer (``O_NONBLOCK``), then read as usual: a pipe a
    running command writes (``/dev/stdin``, ``<(...)``) is read whole, and a named pipe nobody has
    opened for writing reads as empty (and is refused as no file of its kind) instead of blocking
    the open until Ctrl-C. A writer that opens the FIFO only later is not waited for. A file
    larger than the bound (``/dev/zero`` behind the name) is refused after reading one byte more.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    max_bytes : int
        Largest content accepted (bytes).
    what : str
        What the file is, for messages (e.g. ``"track file"``).

    Returns
    -------
    bytes

    Raises
    ------
    InputTypeError
        If ``path`` is not a str or path; InputError if it is empty.
    UnreadableFile
        If it cannot be opened or read (absent, a directory, no permission): an OSError and a
        BadInput.
    InputError
        If it is larger than ``max_bytes``; the message names the file.
    """
    path = _as_path(path, "path")
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as err:
        raise unreadable_file(err, os.fspath(path)) from None
    try:
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)  # the open did not wait for a writer; the reads do
        chunks, size = [], 0
        while size <= max_bytes:
            chunk = os.read(fd, min(1 << 20, max_bytes + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as err:  # EISDIR: a directory opens, and fails at its first read
        why = "a directory, not a file" if isinstance(err, IsADirectoryError) else None
        raise unreadable_file(err, os.fspath(path), why) from None
    finally:
        os.close(fd)
    if size > max_bytes:
        raise InputError(f"{path}: larger than {max_bytes} bytes: not a {what}")
    return b"".join(chunks)


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
    data = read_bytes(path, max_bytes, what)
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


def read_npz(path: str | os.PathLike, max_bytes: int, names: tuple[str, ...], what: str = "file") -> dict:
    """Arrays of a NumPy ``.npz`` file, each member's header checked against its stored size first.

    :func:`numpy.load` allocates what a member's ``.npy`` header claims: a header that lies (a
    shape of hundreds of GiB over a few stored bytes) would raise a raw ``MemoryError``, or take
    the machine's memory. Here the archive's members are sized before any is read, their headers
    are read alone and must claim exactly the bytes stored, in a dtype without Python objects
    (never a pickle), and only then are the arrays read.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    max_bytes : int
        Largest file, and largest total of its members once inflated (bytes).
    names : tuple of str
        The members to read (without ``.npy``).
    what : str
        What the file is, for messages.

    Returns
    -------
    dict
        ``{name: numpy.ndarray}``.

    Raises
    ------
    OSError
        If it cannot be opened or read.
    InputError
        If it is a link, too large, not an archive, lacks a member, or a member's header does not
        match what it stores; one line naming the file.
    """
    import zipfile

    source = os.fspath(_as_path(path, "path"))
    if os.path.islink(source) or not os.path.isfile(source):
        raise InputError(f"{source}: not a regular file: not a {what}")
    if os.path.getsize(source) > max_bytes:
        raise InputError(f"{source}: larger than {max_bytes} bytes: not a {what}")
    try:
        with zipfile.ZipFile(source) as archive:
            members = {info.filename: info for info in archive.infolist()}
            if sum(info.file_size for info in members.values()) > max_bytes:
                raise InputError(f"{source}: its members inflate to more than {max_bytes} bytes: not a {what}")
            out = {}
            for name in names:
                info = members.get(f"{name}.npy")
                if info is None:
                    raise InputError(f"{source}: no member {name!r}: not a {what}")
                with archive.open(info) as fh:
                    out[name] = _npy_member(fh, info.file_size, f"{source}[{name!r}]")
    except (zipfile.BadZipFile, zipfile.LargeZipFile, EOFError, zlib.error, ValueError) as err:
        if isinstance(err, InputError):
            raise
        first = str(err).splitlines()[0] if str(err) else "damaged"
        raise InputError(f"{source}: not a readable .npz {what} ({type(err).__name__}: {first})") from None
    return out


def _npy_member(fh, stored: int, source: str):
    """One ``.npy`` member: its header read and checked against ``stored`` bytes, then its array."""
    import numpy as np

    version = np.lib.format.read_magic(fh)
    header = {(1, 0): np.lib.format.read_array_header_1_0,
              (2, 0): np.lib.format.read_array_header_2_0}.get(version)
    if header is None:
        raise InputError(f"{source}: an .npy format version {version} this package does not read")
    shape, fortran, dtype = header(fh, max_header_size=10_000)
    if dtype.hasobject:
        raise InputError(f"{source}: holds Python objects (a pickle): never read")
    claimed = dtype.itemsize
    for n in shape:
        claimed *= int(n)
    if claimed != stored - fh.tell():
        raise InputError(f"{source}: its header claims {claimed} bytes of data, the file stores "
                         f"{stored - fh.tell()}: damaged or forged")
    data = np.frombuffer(fh.read(claimed), dtype=dtype)
    return data.reshape(shape, order="F" if fortran else "C").copy()


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
            # inflated a megabyte at a time and counted, never held: a bomb costs time, not memory
            inflater, pending = zlib.decompressobj(), data[pos + 8:pos + 8 + nbytes]
            try:
                while pending and total <= limit:
                    total += len(inflater.decompress(pending, 1 << 20))
                    pending = inflater.unconsumed_tail
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
        ``max_bytes`` (the package writes its ``.mat`` files uncompressed: their variables take
        what the file takes). A small file whose compressed variable inflates to gigabytes is
        refused after inflating at most this much, counted a megabyte at a time, never held.
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
    data = read_bytes(path, max_bytes, what)
    if data[:8] == b"\x89HDF\r\n\x1a\n" or data[512:520] == b"\x89HDF\r\n\x1a\n" or data[124:126] == b"\x00\x02":
        raise InputError(f"{path}: a MATLAB v7.3 (HDF5) file: save the {what} with -v7 (format 5)")
    if len(data) < 128 or not data.startswith(_MAT5_HEADER) or data[126:128] not in (b"IM", b"MI"):
        raise InputError(f"{path}: not a MATLAB 5 .mat file ({len(data)} bytes without its header): "
                         f"not a {what}")
    _mat_inflated_size(data, max_bytes if max_inflated is None else max_inflated, str(path))
    import scipy.io  # here, not at the top: it costs ~0.15 s of every command line's start-up

    try:
        content = scipy.io.loadmat(io.BytesIO(data), squeeze_me=simplify, simplify_cells=simplify)
    except Exception as err:  # scipy's MatReadError, ValueError, IndexError, ... of a damaged file
        raise InputError(f"{path}: not a readable MAT file ({type(err).__name__}: "
                         f"{str(err).splitlines()[0] if str(err) else 'corrupt'})") from None
    return {k: v for k, v in content.items() if not k.startswith("__")}
