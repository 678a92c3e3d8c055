"""Nothing the package loads can run code: a pickle payload planted in every loader's path.

The payload is a pickle whose loading creates a marker file (``open(marker, "w")``). It is planted
under the cache's predictable names (the current ``.json`` and an older version's ``.pkl``) and
under every name the file loaders read: system files (JSON, CSV, MAT), boundary files (JSON, MAT,
and an ``.npz``), track files and CSV tables. Each loader must refuse or ignore it, and the marker
must never appear. A control test shows that the payload does run when unpickled, so the
assertions can fail.
"""

from __future__ import annotations

import pickle
import time

import pytest

import semitrack as st
from semitrack.base import records
from semitrack.base.errors import BadInput
from semitrack.equivalent import cache

SMALL = dict(n_bars=2, band=(3, 300), n_starts=1, max_nfev=20)


class Payload:
    """Pickles to a call of ``open(marker, "w")``: code run by whoever unpickles it."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


@pytest.fixture
def payload(tmp_path):
    marker = tmp_path / "RAN"
    return marker, pickle.dumps(Payload(marker))


def test_the_payload_runs_when_unpickled(payload):
    # the control: the marker appears when the bytes are unpickled, so its absence below means something
    marker, data = payload
    pickle.loads(data).close()
    assert marker.exists()


def test_the_cache_never_unpickles_a_planted_file(payload, tmp_path, monkeypatch):
    marker, data = payload
    folder = tmp_path / "shared-cache"
    folder.mkdir()
    track = st.slab_track()
    key = cache.fit_cache_key(track, "slab", **SMALL)
    for name in (f"fit-{key}.json", f"fit-{key}.pkl"):  # today's name and an older version's
        (folder / name).write_bytes(data)
    sweep_key = cache.response_cache_key(track, [100.0])
    (folder / f"response-{sweep_key}.json").write_bytes(data)
    cache.clear_fit_memo()
    start = time.perf_counter()
    fit = st.cached_fit(track, "slab", cache_dir=folder, **SMALL)
    sweep = cache.cached_central_response(track, [100.0], "transfer", cache_dir=folder)
    cache.clear_fit_memo()
    assert not marker.exists()
    assert fit.n_bars == 2 and sweep.response.w1.shape == (1,)
    # the planted file was replaced by data: JSON that builds only the package's result types
    back = records.loads((folder / f"fit-{key}.json").read_text(), cache._record_types())
    assert back.cost == fit.cost
    assert time.perf_counter() - start < 30


def test_a_record_file_builds_only_the_types_it_is_given():
    text = records.dumps({"x": 1.5})
    assert records.loads(text, {}) == {"x": 1.5}
    with pytest.raises(BadInput, match="'Payload', which is not one of"):
        records.loads('{"r": "Payload", "v": {"marker": "x"}}', {})
    with pytest.raises(BadInput, match="dtype"):
        records.loads('{"a": "|O", "shape": [1], "b64": "AAAAAAAAAAA="}', {})
    with pytest.raises(BadInput, match="not JSON"):
        records.loads("[" * 100_000, {})
    with pytest.raises(BadInput, match="nests deeper"):
        records.loads('{"list": [' * 40 + "1" + "]}" * 40, {})
    with pytest.raises(BadInput, match="not a list"):
        records.loads('{"list": {"a": 1}}', {})


LOADERS = {  # file name -> the loader that reads it
    "system.json": st.load_system_json,
    "system.csv": st.load_system_csv,
    "system.mat": st.load_system_mat,
    "boundary.json": st.load_boundary,
    "boundary.mat": st.load_boundary,
    "boundary.npz": st.load_boundary,
    "track.toml": st.load_track_toml,
    "pad.csv": st.load_frequency_table,
}


@pytest.mark.parametrize("name", sorted(LOADERS))
def test_no_loader_runs_a_planted_pickle(payload, tmp_path, name):
    marker, data = payload
    path = tmp_path / name
    path.write_bytes(data)
    start = time.perf_counter()
    with pytest.raises(BadInput) as info:
        LOADERS[name](path)
    message = str(info.value)
    assert len(message.splitlines()) == 1 and str(path) in message, message
    assert not marker.exists()
    assert path.read_bytes() == data  # left as it was
    assert time.perf_counter() - start < 5
