"""The package's cache folders under hostile conditions: checked before the work, links never followed.

Two caches write files into a folder the user names: the moving Green's functions' kernels
(``cache=``, :mod:`semitrack.fe.kernelcache`) and the fits and sweeps (``cache_dir=``,
:mod:`semitrack.equivalent.cache`). Each used to write through a symbolic link planted under one
of its file names (replacing a file outside the folder), found a folder it could not use only
after the set-up it was asked to keep (the result lost), wrote ``cache=""`` into the current
directory, and read a kernel file whose ``.npy`` header lies about its size into a raw
``MemoryError``. Here each of those is held to the rule: a folder that cannot hold the cache is
refused at once naming the parameter; a link planted in it is replaced, its target left as it was;
a forged member is never allocated.
"""

from __future__ import annotations

import io
import os
import zipfile
from pathlib import Path

import numpy as np
import pytest
from refusals import refused

import semitrack as st
from semitrack.base.errors import InputError
from semitrack.base.files import read_npz
from semitrack.equivalent.cache import cached_central_response, clear_fit_memo
from semitrack.fe.kernelcache import cached_kernels, clear_kernel_memo
from semitrack.fe.kernels import grid_of

SLAB = st.slab_track(damping="viscous")
NE, SPEED, DT, MEMORY = 8, 50.0, 1e-4, 300  # coarse kernels: the cache's rules hold for any


def _kernels(cache):
    return cached_kernels(SLAB, NE, None, grid_of(SLAB, SPEED, DT), MEMORY, None, cache)


def _outside(tmp_path: Path) -> Path:
    victim = tmp_path / "outside" / "precious.txt"
    victim.parent.mkdir()
    victim.write_text("the user's own file")
    return victim


@pytest.fixture()
def kernel_file(tmp_path) -> Path:
    """The name a kernel file gets in ``tmp_path / 'cache'`` (written once, then removed)."""
    clear_kernel_memo()
    _kernels(tmp_path / "cache")
    (path,) = (tmp_path / "cache").glob("kernels-*.npz")
    clear_kernel_memo()
    return path


# --- links planted in the folder ---------------------------------------------------------------------
def test_a_link_planted_as_the_kernel_file_is_replaced_not_written_through(tmp_path, kernel_file):
    victim = _outside(tmp_path)
    kernel_file.unlink()
    kernel_file.symlink_to(victim)
    kernels = _kernels(kernel_file.parent)
    assert victim.read_text() == "the user's own file"
    assert kernel_file.is_file() and not kernel_file.is_symlink()
    clear_kernel_memo()
    assert _kernels(kernel_file.parent).elapsed == kernels.elapsed  # and it reads back


def test_a_link_planted_as_the_lock_file_is_replaced(tmp_path, kernel_file):
    victim = _outside(tmp_path)
    kernel_file.unlink()
    lock = Path(f"{kernel_file}.lock")
    lock.unlink()
    lock.symlink_to(victim)
    _kernels(kernel_file.parent)
    assert victim.read_text() == "the user's own file" and not lock.is_symlink()


def test_a_link_to_another_kernel_file_is_not_read(tmp_path, kernel_file):
    elsewhere = tmp_path / "elsewhere.npz"
    kernel_file.rename(elsewhere)
    kernel_file.symlink_to(elsewhere)
    assert _kernels(kernel_file.parent) is not None
    assert not kernel_file.is_symlink() and elsewhere.is_file()


def test_a_link_planted_in_the_fit_cache_is_replaced(tmp_path):
    folder = tmp_path / "fits"
    clear_fit_memo()
    cached_central_response(SLAB, [100.0, 200.0], "transfer", cache_dir=folder)
    (path,) = folder.glob("response-*.json")
    victim = _outside(tmp_path)
    path.unlink()
    path.symlink_to(victim)
    clear_fit_memo()
    sweep = cached_central_response(SLAB, [100.0, 200.0], "transfer", cache_dir=folder)
    assert victim.read_text() == "the user's own file" and path.is_file() and not path.is_symlink()
    assert sweep.response.alpha.shape == (2, 2, 2)


# --- the folder, before the work ---------------------------------------------------------------------
def _loop(tmp_path: Path) -> Path:
    loop = tmp_path / "loop"
    loop.symlink_to(tmp_path / "loop")
    return loop


def _file(tmp_path: Path) -> Path:
    path = tmp_path / "a-file"
    path.write_text("not a folder")
    return path


def _dangling(tmp_path: Path) -> Path:
    link = tmp_path / "dangling"
    link.symlink_to(tmp_path / "nowhere" / "at-all")
    return link


def _under_a_file(tmp_path: Path) -> Path:
    return _file(tmp_path) / "sub"


FOLDERS = {"empty": (lambda p: "", "must name a folder"), "a file": (_file, "is a file"),
           "a link loop": (_loop, "leads to no folder"), "a dangling link": (_dangling, "leads to no folder"),
           "under a file": (_under_a_file, "cannot be created")}


@pytest.mark.parametrize("case", list(FOLDERS))
def test_a_folder_that_cannot_hold_the_kernels_is_refused_before_the_set_up(tmp_path, case):
    make, words = FOLDERS[case]
    folder = make(tmp_path)
    clear_kernel_memo()
    refused(lambda: _kernels(folder), InputError, "cache", words, cpu=0.3)  # the set-up (0.5 s of CPU) not begun
    refused(lambda: st.moving_green_response(SLAB, st.Wheel(), speed=SPEED, dt=DT, duration=0.05,
                                             elements_per_bay=NE, cache=folder), InputError, "cache", words)


@pytest.mark.parametrize("case", list(FOLDERS))
def test_a_folder_that_cannot_hold_the_fits_is_refused(tmp_path, case):
    make, words = FOLDERS[case]
    folder = make(tmp_path)
    clear_fit_memo()
    refused(lambda: cached_central_response(SLAB, [100.0], "transfer", cache_dir=folder), InputError,
            "cache_dir", words, cpu=1.0)


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root writes into a read-only folder")
def test_a_read_only_folder_is_refused_before_the_set_up(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o555)
    clear_kernel_memo()
    refused(lambda: _kernels(folder), InputError, "cache", "not writable", cpu=0.3)


def test_a_new_folder_is_created_with_its_parents(tmp_path):
    clear_kernel_memo()
    _kernels(tmp_path / "a" / "b")
    assert len(list((tmp_path / "a" / "b").glob("kernels-*.npz"))) == 1


# --- members that lie about their size ---------------------------------------------------------------
def _forged(path: Path, member: str, shape: tuple) -> None:
    """Rewrite ``path`` (an .npz) with ``member``'s header claiming ``shape``, its data unchanged."""
    with zipfile.ZipFile(path) as archive:
        members = {info.filename: archive.read(info) for info in archive.infolist()}
    data = members[f"{member}.npy"]
    fh = io.BytesIO(data)
    version = np.lib.format.read_magic(fh)
    _, fortran, dtype = np.lib.format.read_array_header_1_0(fh) if version == (1, 0) else \
        np.lib.format.read_array_header_2_0(fh)
    body = data[fh.tell():]
    head = io.BytesIO()
    np.lib.format.write_array_header_1_0(head, {"descr": np.lib.format.dtype_to_descr(dtype),
                                                "fortran_order": fortran, "shape": shape})
    members[f"{member}.npy"] = head.getvalue() + body  # the writer puts the magic string first
    with zipfile.ZipFile(path, "w") as archive:
        for name, content in members.items():
            archive.writestr(name, content)


def test_a_member_whose_header_lies_is_never_allocated(tmp_path, kernel_file):
    _forged(kernel_file, "loop", (1 << 20, 1 << 20, 45))  # 363 TiB claimed over the stored bytes
    with pytest.raises(InputError, match="header claims"):
        read_npz(kernel_file, 1 << 31, ("loop",), "kernel file")
    clear_kernel_memo()
    again = _kernels(kernel_file.parent)  # unreadable: computed again and written over
    assert again.loop.shape[-1] == MEMORY
    assert read_npz(kernel_file, 1 << 31, ("loop",))["loop"].shape == again.loop.shape


def test_objects_in_a_member_are_never_read(tmp_path):
    path = tmp_path / "objects.npz"
    np.savez(path, loop=np.array([{"a": 1}], dtype=object))
    with pytest.raises(InputError, match="Python objects"):
        read_npz(path, 1 << 20, ("loop",))


@pytest.mark.parametrize("damage", ["truncated", "missing member", "not a zip"])
def test_a_damaged_archive_is_refused_naming_the_file(tmp_path, damage):
    path = tmp_path / "k.npz"
    np.savez(path, loop=np.zeros((3, 4)), key=np.array("{}"))
    if damage == "truncated":
        path.write_bytes(path.read_bytes()[:100])
    elif damage == "not a zip":
        path.write_bytes(b"\x80\x04 a pickle's first bytes")
    names = ("loop", "release") if damage == "missing member" else ("loop",)
    refused(lambda: read_npz(path, 1 << 20, names, "kernel file"), InputError, str(path))
