"""Broadband ends fitted once (:func:`semitrack.cached_boundary`): the fit itself, once per process and per folder."""

from __future__ import annotations

import numpy as np
import pytest

import semitrack as st
from semitrack.boundary import cache
from semitrack.equivalent.cache import clear_fit_memo

TRACK = st.slab_track(damping="viscous")
SMALL = {"band": (3.0, 300.0), "n_poles": 4, "df": 30.0, "n_iter": 3}


@pytest.fixture
def counted(monkeypatch):
    """The fits cached_boundary computes, with an empty in-process memo."""
    calls = []
    real = cache.fit_boundary

    def counting(**arguments):
        calls.append(arguments)
        return real(**arguments)

    clear_fit_memo()
    monkeypatch.setattr(cache, "fit_boundary", counting)
    yield calls
    clear_fit_memo()


def _same(a: st.BroadbandBoundary, b: st.BroadbandBoundary) -> None:
    """Equal field by field, bit for bit, and so the same M, C, K."""
    for name in ("poles", "coefficients", "K0", "D"):
        assert np.array_equal(getattr(a.rational, name), getattr(b.rational, name)), name
    assert (a.band, a.enforcement_rounds, a.track_damping) == (b.band, b.enforcement_rounds, b.track_damping)
    assert {n: t._replace(elapsed=0.0) for n, t in a.orders_tried.items()} == {  # the fit times aside
        n: t._replace(elapsed=0.0) for n, t in b.orders_tried.items()}
    assert (a.errors.median, a.errors.max, list(a.errors.per_element)) == (
        b.errors.median, b.errors.max, list(b.errors.per_element))
    assert all(np.array_equal(a.errors.per_element[k], b.errors.per_element[k]) for k in a.errors.per_element)
    ma, mb = a.matrix_system(), b.matrix_system()
    assert all(np.array_equal(getattr(ma, n), getattr(mb, n)) for n in ("M", "C", "K"))


def test_it_is_fit_boundary_computed_once_per_process(counted):
    first = st.cached_boundary(TRACK, **SMALL)
    assert st.cached_boundary(TRACK, band=(3, 300), n_poles=4, df=30.0, n_iter=3, seed=0) is first  # defaults filled in
    assert len(counted) == 1
    _same(first, st.fit_boundary(TRACK, **SMALL))
    st.cached_boundary(TRACK, **(SMALL | {"n_poles": 6}))
    assert len(counted) == 2  # another argument: another fit


def test_a_folder_is_read_back_bit_for_bit_and_a_damaged_file_recomputed(counted, tmp_path):
    folder = tmp_path / "cache"  # created by cached_boundary
    first = st.cached_boundary(TRACK, cache_dir=folder, **SMALL)
    (path,) = folder.glob("boundary-*.json")
    clear_fit_memo()  # a fresh process
    back = st.cached_boundary(TRACK, cache_dir=folder, **SMALL)
    assert back is not first and len(counted) == 1
    _same(back, first)
    assert back.orders_tried == first.orders_tried and list(back.orders_tried) == [4]  # int keys kept
    path.write_text(path.read_text()[:-40])  # cut short: recomputed and rewritten
    clear_fit_memo()
    _same(st.cached_boundary(TRACK, cache_dir=folder, **SMALL), first)
    assert len(counted) == 2
    clear_fit_memo()
    st.cached_boundary(TRACK, cache_dir=folder, **SMALL)
    assert len(counted) == 2  # the rewritten file read


def test_a_record_of_another_type_in_its_place_is_not_read(counted, tmp_path):
    st.cached_boundary(TRACK, cache_dir=tmp_path, **SMALL)
    (path,) = tmp_path.glob("boundary-*.json")
    path.write_text('{"r": "FitResult", "v": {}}')
    clear_fit_memo()
    assert isinstance(st.cached_boundary(TRACK, cache_dir=tmp_path, **SMALL), st.BroadbandBoundary)
    assert len(counted) == 2


def test_the_folder_and_the_arguments_are_checked_before_the_fit(counted, tmp_path):
    blocker = tmp_path / "a file"
    blocker.write_text("")
    with pytest.raises(st.BadInput, match="cache_dir"):
        st.cached_boundary(TRACK, cache_dir=blocker, **SMALL)
    with pytest.raises(st.BadInput, match="band"):
        st.cached_boundary(TRACK, band=(300.0, 3.0))
    with pytest.raises(st.BadInput, match="track"):
        st.cached_boundary("slab", **SMALL)
    with pytest.raises(TypeError, match="n_bars"):
        st.cached_boundary(TRACK, n_bars=5)
    with pytest.raises(st.BadInput, match="n_poles: a cache cannot key an argument of type set"):
        st.cached_boundary(TRACK, band=(3.0, 300.0), n_poles={4})
    assert counted == []


def test_the_key_follows_every_argument_and_the_track_but_not_its_name():
    key = cache.boundary_cache_key(TRACK, **SMALL)
    assert key == cache.boundary_cache_key(TRACK.replace(name="renamed"), **SMALL)
    assert key != cache.boundary_cache_key(TRACK.replace(kv=1.01 * TRACK.kv), **SMALL)
    assert key != cache.boundary_cache_key(TRACK, **(SMALL | {"seed": 1}))
    assert key != cache.boundary_cache_key(TRACK, **(SMALL | {"band": (3.0, 301.0)}))


@pytest.mark.parametrize("keys", [{1: "a", 7: (2.5, None)}, {}])
def test_a_record_keeps_a_dict_with_integer_keys(keys):
    from semitrack.base import records
    assert records.loads(records.dumps(keys), {}) == keys


@pytest.mark.parametrize("text, says", [('{"di": [[1, 2], [1, 3]]}', "repeats a key"),
                                        ('{"di": [["1", 2]]}', "not an \\[int, value\\] pair"),
                                        ('{"di": [[true, 2]]}', "not an \\[int, value\\] pair"),
                                        ('{"di": {"1": 2}}', "holds a dict, not a list")])
def test_a_malformed_integer_keyed_dict_is_refused(text, says):
    from semitrack.base import records
    with pytest.raises(st.BadInput, match=says):
        records.loads(text, {})
