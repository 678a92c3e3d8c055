"""Round trips and robustness of the exports of equivalent systems."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.io

import semitrack.equivalent.io as sio
from semitrack.equivalent.systems import BallastedEquivalent, SlabEquivalent
from semitrack.paper.systems import paper_table4, paper_table7

F = np.array([3.0, 117.0, 183.0, 489.0, 900.0, 3000.0])

# JSON and CSV store numbers with 17 significant digits and .mat stores doubles, so a round trip
# should be exact; 1e-10 (the requirement) leaves room for any platform's float formatting.
RT_RTOL = 1e-10

ONE_BAR = SlabEquivalent(m=5.0, J=0.1, L=0.3, k=1e7, c_l=10.0, c_r=20.0, k_phi=[], c_phi=[])
ONE_BAR_B = BallastedEquivalent(m=5.0, J=0.1, L=0.3, k=1e7, c_l=10.0, c_r=20.0, k_phi=[], c_phi=[],
                                mu=3.0, s=2e7, d_l=5.0, d_r=6.0)
SYSTEMS = [paper_table4(), paper_table7(), ONE_BAR, ONE_BAR_B]
IDS = ["table4", "table7", "slab1", "ballasted1"]


def assert_same_system(a, b):
    assert type(a) is type(b)
    for X, Y in zip(a.matrices(), b.matrices()):
        np.testing.assert_allclose(X, Y, rtol=RT_RTOL, atol=0)
    np.testing.assert_allclose(a.receptance(F), b.receptance(F), rtol=RT_RTOL, atol=0)


@pytest.mark.parametrize("system", SYSTEMS, ids=IDS)
def test_json_round_trip(system, tmp_path):
    path = sio.save_system_json(system, tmp_path / "sys.json")
    back = sio.load_system_json(path)
    assert_same_system(back, system)
    assert back == system  # repr of floats is exact
    data = json.loads(path.read_text())
    assert data["layout"] == system.layout
    assert data["parameters"]["m"]["unit"] == "kg"
    assert data["dof_names"] == system.dof_names()
    assert data["matrices"]["K"]["entry_units"][0][0] == "N/m"
    assert data["matrices"]["M"]["entry_units"][1][1] == "N m s^2/rad"


@pytest.mark.parametrize("system", SYSTEMS, ids=IDS)
def test_csv_round_trip(system, tmp_path):
    path = sio.save_system_csv(system, tmp_path / "sys.csv")
    back = sio.load_system_csv(path)
    assert_same_system(back, system)
    text = path.read_text()
    assert "[parameters]" in text and "[K]" in text and "k_phi,N m/rad" in text


@pytest.mark.parametrize("system", SYSTEMS, ids=IDS)
def test_mat_round_trip(system, tmp_path):
    path = sio.save_system_mat(system, tmp_path / "sys.mat")
    raw = scipy.io.loadmat(path)
    for name, X in zip("MCK", system.matrices()):
        np.testing.assert_allclose(raw[name], X, rtol=RT_RTOL, atol=0)
    assert [str(np.squeeze(x)) for x in raw["dof_names"].ravel()] == system.dof_names()
    assert str(raw["layout"][0]) == system.layout
    assert_same_system(sio.load_system_mat(path), system)


def test_export_dispatch(tmp_path):
    t7 = paper_table7()
    for suffix in ("json", "csv", "mat"):
        assert sio.export_system(t7, tmp_path / f"x.{suffix}").exists()
    assert sio.export_system(t7, tmp_path / "noext", format="json").exists()
    with pytest.raises(ValueError, match="format must be one of"):
        sio.export_system(t7, tmp_path / "x.txt")
    with pytest.raises(TypeError, match="system must be"):
        sio.save_system_json({"m": 1}, tmp_path / "y.json")
    with pytest.raises(TypeError, match="path must be"):
        sio.save_system_json(t7, 42)


def test_failed_write_leaves_no_file(tmp_path, monkeypatch):
    target = tmp_path / "sys.json"
    sio.save_system_json(paper_table4(), target)
    before = target.read_bytes()

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(sio.json, "dump", boom)
    with pytest.raises(RuntimeError, match="disk full"):
        sio.save_system_json(paper_table7(), target)
    with pytest.raises(RuntimeError, match="disk full"):
        sio.save_system_json(paper_table7(), tmp_path / "new.json")
    assert target.read_bytes() == before  # the old file is untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sys.json"]  # no temp files, no new file


def test_corrupt_files(tmp_path):
    path = sio.save_system_json(paper_table4(), tmp_path / "sys.json")
    data = json.loads(path.read_text())
    data["matrices"]["K"]["values"][0][0] *= 2
    path.write_text(json.dumps(data))
    with pytest.warns(UserWarning, match="stored K differs"):
        back = sio.load_system_json(path)
    assert back == paper_table4()  # parameters win
    data["parameters"]["m"]["values"][0] = -1.0
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"m\[0\] must be non-negative"):
        sio.load_system_json(path)
    data["format"] = "something else"
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="'format' must be"):
        sio.load_system_json(path)
    bad_csv = tmp_path / "bad.csv"
    bad_csv.write_text("m,1,2\n")
    with pytest.raises(ValueError, match="before the first"):
        sio.load_system_csv(bad_csv)


@pytest.mark.parametrize("system", SYSTEMS, ids=IDS)
def test_files_state_the_highest_natural_frequency(system, tmp_path):
    f_max, dt = system.highest_natural_frequency(), system.central_difference_time_step()
    assert f_max > 0 and dt == pytest.approx(2 / (2 * np.pi * f_max), rel=1e-12)
    meta = json.loads(sio.save_system_json(system, tmp_path / "sys.json").read_text())["metadata"]
    assert meta["highest_natural_frequency"] == {**meta["highest_natural_frequency"], "unit": "Hz", "value": f_max}
    assert meta["central_difference_time_step"]["unit"] == "s"
    assert meta["central_difference_time_step"]["value"] == pytest.approx(dt, rel=1e-15)
    csv_text = sio.save_system_csv(system, tmp_path / "sys.csv").read_text()
    assert f"highest_natural_frequency_Hz,{f_max!r}" in csv_text
    raw = scipy.io.loadmat(sio.save_system_mat(system, tmp_path / "sys.mat"), simplify_cells=True)
    assert raw["highest_natural_frequency_Hz"] == pytest.approx(f_max, rel=1e-15)


def test_json_without_metadata_still_loads(tmp_path):
    """Files written before the metadata existed load as before (the reader ignores it)."""
    data = sio.system_to_dict(paper_table7())
    del data["metadata"]
    path = tmp_path / "old.json"
    path.write_text(json.dumps(data))
    assert sio.load_system_json(path) == paper_table7()


def test_json_metadata_of_a_system_without_inertia_is_valid_json(tmp_path):
    massless = SlabEquivalent(m=0.0, J=0.0, L=0.3, k=1e7, c_l=10.0, c_r=20.0, k_phi=[], c_phi=[])
    text = sio.save_system_json(massless, tmp_path / "sys.json").read_text()
    meta = json.loads(text, parse_constant=lambda name: pytest.fail(f"non-standard JSON {name}"))["metadata"]
    assert meta["highest_natural_frequency"]["value"] == 0.0
    assert meta["central_difference_time_step"]["value"] is None
