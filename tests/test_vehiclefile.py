"""Vehicle files, a track file's changes and the two-column series files: read back to what was written.

Independent checks: a vehicle written and read is the same vehicle (its matrices equal), the
shipped bogie is st.Bogie with the file's numbers; the changes a file states are the dict typed
here; a spectrum file's levels give the same roughness as the arrays, and a profile file the same
RailProfile; every refusal names the file and the rule.
"""

from __future__ import annotations

import numpy as np
import pytest

import semitrack as st
from semitrack.model.trackfile import example_path
from semitrack.model.vehiclefile import vehicle_example_path


@pytest.mark.parametrize("vehicle", [st.Bogie(body_mass=1e4), st.WheelGroup((st.Wheel(mass=500.0),)),
                                     st.WheelGroup((st.Wheel(),) * 3, (0.0, -2.5, -15.0))])
def test_a_vehicle_file_reads_back_to_the_same_vehicle(tmp_path, vehicle):
    path = tmp_path / "v.toml"
    path.write_text(st.vehicle_to_toml(vehicle, name="mine"))
    back = st.load_vehicle_toml(path)
    assert type(back) is type(vehicle) and back == vehicle
    for a, b in zip(back.matrices(), vehicle.matrices()):
        np.testing.assert_array_equal(a, b)


def test_the_shipped_bogie_is_the_file_s_numbers():
    bogie = st.load_vehicle_toml(vehicle_example_path("bogie"))
    assert bogie == st.Bogie(wheel=st.Wheel(mass=600.0, preload=1e5, hertz_constant=9.3e10, primary_stiffness=1.2e6,
                                            primary_damping=1.5e4, radius=0.46), body_mass=1e4)
    assert st.load_vehicle_toml(vehicle_example_path("wheel")).wheels == (st.Wheel(),)


@pytest.mark.parametrize("text, words", [
    ('type = "tram"\n', "type must be one of"),
    ('type = "bogie"\n[bogie]\nwheelbase = -1.0\n', "line 3: [bogie] wheelbase"),
    ('type = "bogie"\n[wheel]\nmas = 600.0\n', "line 3: [wheel]: unknown key 'mas'"),
    ('type = "bogie"\n[wheel]\nprimary_stiffness = 0.0\n', "primary_stiffness must be > 0"),
    ('type = "wheels"\n[wheel]\nmass = 600.0\n', "spacing must be a list of offsets"),
    ('type = "wheel"\n[bogie]\nwheelbase = 2.5\n', "unknown key 'bogie' for type = 'wheel'"),
    ('type = "wheel"\n[wheel]\nmass = "600"\n', "mass"),
])
def test_a_bad_vehicle_file_is_refused_by_name(tmp_path, text, words):
    path = tmp_path / "v.toml"
    path.write_text(text)
    with pytest.raises(st.TrackFileError) as caught:
        st.load_vehicle_toml(path)
    assert words in str(caught.value) and str(path) in str(caught.value) and "\n" not in str(caught.value)


def test_a_track_file_s_changes_are_what_it_states_and_load_track_toml_does_not_drop_them(tmp_path):
    path = tmp_path / "t.toml"
    path.write_text(example_path("ballasted").read_text() + "\n[[changes]]\nsupport = -1\nkv = 2e7\n"
                    "[[changes]]\nsupport = 0\nkb = 0.0\ngap = 5e-4\n[[changes]]\nsupport = 3\nfailed = true\n")
    track, local = st.load_track_file(path)
    assert track == st.load_track_toml(example_path("ballasted"))
    assert local.changes == {-1: {"kv": 2e7}, 0: {"kb": 0.0}, 3: None} and local.gaps == {0: 5e-4}
    with pytest.raises(st.TrackFileError, match=r"line \d+: the file holds local changes \(\[\[changes\]\]\)"):
        st.load_track_toml(path)
    plain, none = st.load_track_file(example_path("slab"))
    assert none.changes == {} and none.gaps == {}


def test_spectrum_and_profile_files_read_as_their_arrays(tmp_path):
    spectrum = tmp_path / "s.csv"
    lam, levels = [0.1, 0.05, 0.025], [5.0, 1.0, -3.0]
    spectrum.write_text("# a measured roughness\nwavelength (m), L (dB re 1 um)\n"
                        + "".join(f"{a},{b}\n" for a, b in zip(lam, levels)))
    w, L = st.load_roughness_spectrum(spectrum)
    np.testing.assert_array_equal(w, lam)
    np.testing.assert_array_equal(L, levels)
    a, b = st.roughness_from_spectrum(20.0, w, L), st.roughness_from_spectrum(20.0, lam, levels)
    np.testing.assert_array_equal(a.amplitudes, b.amplitudes)
    profile = tmp_path / "p.csv"
    profile.write_text("x_m, r_m\n0.0, 0.0\n0.1, 1e-5\n0.2, 0.0\n")
    read = st.load_rail_profile(profile)
    np.testing.assert_array_equal(read.x, [0.0, 0.1, 0.2])
    np.testing.assert_array_equal(read.r, [0.0, 1e-5, 0.0])
    for text, words in [("x_mm, r_mm\n0, 0\n", "names mm"), ("f, re\n1, 2\n", "cannot tell a spectrum from a profile"),
                        ("x_m, r_m\n0.0, 0.0\n0.1, abc\n", "line 3: r is not a number"),
                        ("x_m, r_m\n0.0, 1e-5\n0.1, 0.0\n", "zero at both ends"),
                        ("x (in), r (in)\n0, 0\n", "names 'in'"), ("x (μm), r (μm)\n0, 0\n", "micrometres"),
                        ("x (ft), r (m)\n0, 0\n", "names 'ft'")]:
        profile.write_text(text)
        with pytest.raises(st.BadInput, match=words):
            st.load_rail_profile(profile)
    with pytest.raises(st.BadInput, match="a roughness spectrum"):
        st.load_rail_profile(spectrum)
    spectrum.write_text("wavelength (ft), level (dB re 1 um)\n1, 2\n")
    with pytest.raises(st.BadInput, match="names 'ft'"):
        st.load_roughness_spectrum(spectrum)
