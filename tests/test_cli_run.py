"""``semitrack run``: a vehicle along a track file with its changes, as the README types it.

Independent check: the CSV's histories equal the API's run of the same inputs (the same route,
track, changes, vehicle and roughness, built here from the package's own calls), and its summary
lines the API's summary; bad input exits 2 in one line and never writes over an input.
"""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pandas as pd
import pytest

import semitrack as st
from semitrack.model.trackfile import example_path
from semitrack.model.vehiclefile import vehicle_example_path

ENV = {"OPENBLAS_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"}
HANGING = "\n[[changes]]\nsupport = 0\nkb = 0.0\ngap = 1e-3\n"


def run(*args, cwd):
    return subprocess.run([sys.executable, "-m", "semitrack", "run", *map(str, args)], capture_output=True,
                          text=True, cwd=cwd, env=ENV, timeout=300)


def one_line(result, *words):
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    for w in words:
        assert w in lines[0], lines[0]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("run")
    (folder / "hanging.toml").write_text(example_path("ballasted").read_text() + HANGING)
    (folder / "bogie.toml").write_text(vehicle_example_path("bogie").read_text())
    return folder


def test_the_readme_s_run_writes_the_api_s_histories_and_a_plot(files):
    result = run("hanging.toml", "bogie.toml", "--roughness", "iso3095", "--speed", 20, "--duration", 0.05,
                 "--watch", 0, 1, "-o", "run.csv", "--plot", "run.png", cwd=files)
    assert result.returncode == 0, result.stderr
    assert (files / "run.png").stat().st_size > 10_000
    table = pd.read_csv(files / "run.csv", comment="#")
    track, local = st.load_track_file(files / "hanging.toml")
    assert local.changes == {0: {"kb": 0.0}} and local.gaps == {0: 1e-3}
    bogie = st.load_vehicle_toml(files / "bogie.toml")
    # the command's period: two lines at least in the band of the longest wavelength (0.4 m, 50 Hz at 20 m/s)
    period = max(0.1, 2.0 / (20.0 / max(st.ISO3095_ROUGHNESS_LIMIT) * (10**0.05 - 10**-0.05)))
    rough = st.roughness_from_spectrum(20.0, period=period, seed=0, dt=2e-5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = st.wheel_rail_response(st.WindowTrack(track, local.changes), bogie, rough, speed=20.0, dt=2e-5,
                                     duration=0.05, watch_supports=[0, 1], ballast_gaps=local.gaps)
    np.testing.assert_allclose(table["t_s"], ref.t, rtol=1e-8)
    np.testing.assert_allclose(table[["leading_wheel_force_N", "trailing_wheel_force_N"]], ref.force, rtol=1e-8)
    np.testing.assert_allclose(table["trailing_wheel_x_m"], ref.x[:, 1], rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(table["support_1_ballast_N"], ref.track_forces.ballast[:, 1], rtol=1e-8, atol=1e-3)
    np.testing.assert_allclose(table["hanging_sleeper_0_ballast_N"], ref.gaps.force[:, 0], rtol=1e-8, atol=1e-3)
    text = (files / "run.csv").read_text()
    peak = ref.summary().loc[("leading wheel", "peak force (kN)"), "value"]
    assert f"# leading wheel: peak force (kN) {peak:.4g}" in text and "route window" in text
    assert "downward positive" in text and "compression positive" in text
    assert "HystereticDampingWarning" not in result.stderr and "warning: the time domain runs the hysteretic" in \
        result.stderr  # the paper's hysteretic track, said once on stderr


def test_standing_wheels_take_the_convolution_and_a_profile_file_rolls(files):
    profile = files / "weld.csv"
    x = np.linspace(0.5, 1.3, 81)
    r = 1e-4 * np.sin(np.pi * (x - 0.5) / 0.8) ** 2
    r[[0, -1]] = 0.0  # the undisturbed rail at both ends
    profile.write_text("# a dip\nx (m), r (m)\n" + "".join(f"{a:.17g},{b:.17g}\n" for a, b in zip(x, r)))
    (files / "wheel.toml").write_text(vehicle_example_path("wheel").read_text())
    standing = run("hanging.toml", "wheel.toml", "--speed", 0, "--duration", 0.03, "-o", "gap.csv", cwd=files)
    assert standing.returncode == 0, standing.stderr  # standing over a gap: the window, which holds gaps
    assert "route window (standing wheels over a gap or a profile" in (files / "gap.csv").read_text()
    forced = run("hanging.toml", "wheel.toml", "--speed", 0, "--duration", 0.03, "--route", "convolution",
                 "-o", "gap2.csv", cwd=files)
    one_line(forced, "--route convolution takes no gaps")
    plain = files / "plain.toml"
    plain.write_text(example_path("ballasted").read_text())
    standing = run("plain.toml", "wheel.toml", "--speed", 0, "--duration", 0.03, "-o", "stand.csv", cwd=files)
    assert standing.returncode == 0, standing.stderr
    assert "route convolution" in (files / "stand.csv").read_text()
    rolling = run("plain.toml", "wheel.toml", "--speed", 10, "--duration", 0.03, "--x", 0.4, "--roughness", "weld.csv",
                  "-o", "roll.csv", cwd=files)
    assert rolling.returncode == 0, rolling.stderr
    table = pd.read_csv(files / "roll.csv", comment="#")
    assert table["wheel_x_m"].iloc[-1] == pytest.approx(0.7)  # from 0.4 m at 10 m/s for 0.03 s, over the dip
    dip = table["wheel_roughness_m"].to_numpy()
    under = np.interp(table["wheel_x_m"], x, r)
    # the wheel's centre path over a 0.8 m dip follows the profile to a few percent (its radius rounds it)
    deep = under > 1e-5
    np.testing.assert_allclose(dip[deep], under[deep], rtol=0.03)
    assert dip.max() > 0.45e-4 and np.all(dip[table["wheel_x_m"] < 0.5] == 0)


@pytest.mark.parametrize("extra, words", [
    (("--speed", -1), "--speed"), (("--speed", 10, "--dt", 0), "--dt"),
    (("--speed", 10, "--duration", 0), "--duration"),
    (("--speed", 0, "--roughness", "iso3095"), "give --speed > 0"),
    (("--speed", 10, "--route", "moving-green"), "--route moving-green takes no [[changes]]"),
    (("--speed", 10, "--roughness", "nowhere.csv"), "nowhere.csv"),
    (("--speed", 10, "--plot", "run.gif"), "--plot"),
    (("--speed", 10, "--watch", "x"), "invalid integer value"),
])
def test_bad_input_exits_2_in_one_line(files, extra, words):
    one_line(run("hanging.toml", "bogie.toml", *extra, "-o", "bad.csv", cwd=files), words)
    assert not (files / "bad.csv").exists()


def test_it_never_writes_over_an_input(files):
    before = (files / "hanging.toml").read_text()
    one_line(run("hanging.toml", "bogie.toml", "--speed", 10, "-o", "hanging.toml", cwd=files), "would replace")
    one_line(run("hanging.toml", "bogie.toml", "--speed", 10, "-o", "run2.csv", "--plot", "bogie.toml", cwd=files),
             "--plot")
    assert (files / "hanging.toml").read_text() == before


@pytest.mark.parametrize("text, words", [
    ("\n[[changes]]\nsupport = 1.5\nkb = 0\n", "support must be the support's index"),
    ("\n[[changes]]\nsupport = 2\n", "changes nothing"),
    ("\n[[changes]]\nsupport = 2\nfailed = true\nkb = 0.0\n", "takes no fields or gap"),
    ("\n[[changes]]\nsupport = 2\ngap = 1e-3\n", "give kb = 0.0 too"),
    ("\n[[changes]]\nsupport = 2\nkbb = 0.0\n", "unknown key 'kbb'"),
    ("\n[[changes]]\nsupport = 2\nkb = 0.0\n[[changes]]\nsupport = 2\nkv = 1e7\n", "changed twice"),
    ("\n[[changes]]\nsupport = 2\nkb = -1.0\n", "changes[2]['kb'] must be non-negative"),
])
def test_a_bad_change_in_the_track_file_is_named(files, text, words):
    (files / "bad.toml").write_text(example_path("ballasted").read_text() + text)
    one_line(run("bad.toml", "bogie.toml", "--speed", 10, "-o", "bad.csv", cwd=files), words)


def test_a_bad_vehicle_file_is_located(files):
    (files / "car.toml").write_text(vehicle_example_path("bogie").read_text().replace("wheelbase", "wheel_base"))
    one_line(run("hanging.toml", "car.toml", "--speed", 10, "-o", "bad.csv", cwd=files), "car.toml, line",
             "unknown key 'wheel_base'")


def test_the_fe_route_and_the_window_agree_on_the_same_files(files):
    """Two routes of one run: the FE model that holds the path and the window that travels (their
    documented agreement is 0.03-0.11 % rms; here a coarse step, within 1 % of the fluctuation)."""
    tables = {}
    for route in ("fe", "window"):
        result = run("hanging.toml", "bogie.toml", "--roughness", "iso3095", "--speed", 20, "--duration", 0.04,
                     "--dt", 1e-4, "--route", route, "-o", f"{route}.csv", cwd=files)
        assert result.returncode == 0, result.stderr
        tables[route] = pd.read_csv(files / f"{route}.csv", comment="#")
    fe, window = (tables[r][["leading_wheel_force_N", "trailing_wheel_force_N"]].to_numpy() for r in ("fe", "window"))
    fluctuation = np.sqrt(np.mean((fe - fe.mean(axis=0)) ** 2))
    assert np.sqrt(np.mean((fe - window) ** 2)) < 0.01 * fluctuation
    one_line(run("hanging.toml", "bogie.toml", "--speed", 20, "--duration", 0.02, "-o", "short.csv", cwd=files),
             "--duration must exceed --ramp")


def test_decay_takes_a_track_file_s_changes(files):
    """``semitrack decay`` on a file with a hanging sleeper: the exact infinite track with that change,
    said in the header; a gap (a contact in time) is refused."""
    path = files / "void.toml"
    path.write_text(example_path("ballasted").read_text() + "\n[[changes]]\nsupport = 0\nkb = 0.0\n")
    result = subprocess.run([sys.executable, "-m", "semitrack", "decay", "void.toml", "--band", "500", "1000", "--df",
                             "10", "-o", "void.csv"], capture_output=True, text=True, cwd=files, env=ENV, timeout=300)
    assert result.returncode == 0, result.stderr
    table = pd.read_csv(files / "void.csv", comment="#")
    expected = st.track_decay_rate(st.InfiniteTrack(st.ballasted_track(), {0: {"kb": 0.0}}), band=(500, 1000),
                                   df=10.0)
    np.testing.assert_allclose(table["decay_rate_dB_per_m"], expected.decay_rate, rtol=1e-5)
    assert "1 changed support;" in (files / "void.csv").read_text()
    refused = subprocess.run([sys.executable, "-m", "semitrack", "decay", "hanging.toml"], capture_output=True,
                             text=True, cwd=files, env=ENV, timeout=300)
    one_line(refused, "a gap under a sleeper")


def test_a_flexible_slab_runs_on_the_fe_model_of_whole_slabs(files):
    """auto on a flexible slab: the FE model that holds the path, its bays a multiple of a slab's fasteners."""
    (files / "floating.toml").write_text(example_path("floating-slab").read_text())
    result = run("floating.toml", "bogie.toml", "--speed", 20, "--duration", 0.03, "--dt", 1e-4, "-o", "fs.csv",
                 cwd=files)
    assert result.returncode == 0, result.stderr
    text = (files / "fs.csv").read_text()
    assert "route fe (a flexible slab" in text
    table = pd.read_csv(files / "fs.csv", comment="#")
    assert table["leading_wheel_force_N"].min() > 0.8e5 and table["trailing_wheel_x_m"].iloc[-1] == pytest.approx(-1.9)
