"""Track files apply the Track's own rules: one rule table, located messages."""

import dataclasses
import json
import re

import numpy as np
import pytest

import semitrack as st
from semitrack.model.trackfile import (
    EXAMPLES,
    SECTIONS,
    SLAB_KEYS,
    SLAB_OPTIONAL_KEYS,
    TrackFileError,
    example_path,
    example_track,
    load_track_toml,
    track_to_toml,
)
from semitrack.model.tracks import FIELD_RULES, SLAB_PARAMETER_INFO

BAD_VALUES = {"positive": [0.0, -1.0, float("inf")], "non-negative": [-0.1, float("nan")], "number": ["x", True]}


TOP_LEVEL = {"name", "damping"}  # keys of the file's top level, not of a section


def test_sections_hold_every_numeric_field_once():
    keys = [key for section in SECTIONS.values() for key in section]
    assert sorted(keys) == sorted(set(FIELD_RULES) - TOP_LEVEL)


@pytest.mark.parametrize("key", sorted(set(FIELD_RULES) - TOP_LEVEL))
def test_a_file_refuses_what_a_track_refuses(tmp_path, key):
    """For every field and bad value: the file's message is the Track's, with file and line."""
    text = example_path("ballasted").read_text()
    line = next(n for n, ln in enumerate(text.splitlines(), 1) if re.match(rf"{key}\s*=", ln))
    base = st.ballasted_track()
    for value in [v for values in BAD_VALUES.values() for v in values]:
        try:
            base.replace(**{key: value})
        except (TypeError, ValueError) as err:
            expected = str(err)
        else:
            continue  # allowed for this field (e.g. kphi = 0)
        toml_value = {True: "true", "x": '"x"'}.get(value, repr(value))  # inf and nan are TOML too
        path = tmp_path / "t.toml"
        path.write_text(re.sub(rf"(?m)^{key}\s*=\s*\S+", f"{key} = {toml_value}", text, count=1))
        with pytest.raises(TrackFileError) as caught:
            load_track_toml(path)
        assert str(caught.value) == f"{path}, line {line}: {expected}"


def test_unknown_key_is_located(tmp_path):
    path = tmp_path / "t.toml"
    path.write_text(example_path("slab").read_text().replace('type = "slab"', 'type = "slab"\nbogus = 1'))
    with pytest.raises(TrackFileError, match="line 6: unknown key 'bogus'"):
        load_track_toml(path)


def test_examples_equal_the_presets():
    """The shipped example files are user-facing copies of the presets' (paper's) numbers."""
    assert load_track_toml(example_path("slab")) == st.slab_track(name="paper slab track")
    assert load_track_toml(example_path("ballasted")) == st.ballasted_track(name="paper ballasted track")


def test_damping_model_round_trips_and_is_checked(tmp_path):
    viscous = st.ballasted_track(damping="viscous")
    path = tmp_path / "viscous.toml"
    path.write_text(track_to_toml(viscous))
    assert load_track_toml(path) == viscous
    assert "damping" not in track_to_toml(st.ballasted_track())  # the paper's files stay as they are
    floating = st.example_track("floating-slab").replace(damping="viscous")  # the slab's families take it too
    path.write_text(track_to_toml(floating))
    assert load_track_toml(path) == floating
    path.write_text(track_to_toml(viscous).replace('"viscous"', '"coulomb"'))
    with pytest.raises(TrackFileError, match=r"line 3.*damping must be one of \('hysteretic', 'viscous'\)"):
        load_track_toml(path)


@pytest.mark.parametrize("kind", ["slab", "ballasted"])
@pytest.mark.parametrize("spacing", [0.3, 0.65, 1.2, 5.0, 1000.0])
def test_plausible_spacings_load(tmp_path, kind, spacing):
    """The paper's tracks and variants of them load: only spacings no track comes near are refused."""
    path = tmp_path / "t.toml"
    path.write_text(re.sub(r"(?m)^spacing\s*=\s*\S+", f"spacing = {spacing!r}", example_path(kind).read_text()))
    assert load_track_toml(path).spacing == spacing


@pytest.mark.parametrize("spacing", ["1000.5", "1e300"])
def test_spacing_beyond_any_track_is_refused(tmp_path, spacing):
    """From ~1e150 m the exact method's scaling overflows; a kilometre is already no railway track."""
    text = example_path("slab").read_text()
    line = next(n for n, ln in enumerate(text.splitlines(), 1) if ln.startswith("spacing"))
    path = tmp_path / "t.toml"
    path.write_text(re.sub(r"(?m)^spacing\s*=\s*\S+", f"spacing = {spacing}", text))
    expected = rf"line {line}: spacing must be at most 1000 m .*got {re.escape(repr(float(spacing)))}"
    with pytest.raises(TrackFileError, match=expected):
        load_track_toml(path)


@pytest.mark.parametrize("content,message", [
    (b'type = "slab"\nname = "caf\xe9"\n', r"not a UTF-8 text track file \(byte 0xe9 at offset 25\)"),
    (b"a = " + b"[" * 3000 + b"]" * 3000, "nested too deeply"),
    (b"# " + b"x" * 1_000_000, "larger than 1000000 bytes"),
])
def test_files_that_are_no_track_files(tmp_path, content, message):
    path = tmp_path / "t.toml"
    path.write_bytes(content)
    with pytest.raises(TrackFileError, match=message):
        load_track_toml(path)


# ---------------------------------------------------------------------------------------------
# The flexible slab: an optional [slab] table holding the fields of st.Slab.

def slab_line(text: str, key: str) -> int:
    """1-based line of ``key = ...`` inside the [slab] table of ``text`` (the rail has an E and I too),
    or of the [slab] header itself for ``key = "[slab]"``."""
    lines = text.splitlines()
    start = next(n for n, ln in enumerate(lines, 1) if ln.startswith("[slab]"))
    if key == "[slab]":
        return start
    return next(n for n, ln in enumerate(lines, 1) if n > start and re.match(rf"{key}\s*=", ln))


def with_slab_value(text: str, key: str, toml_value: str) -> tuple[str, int]:
    """``text`` with ``key = toml_value`` in its [slab] table (replaced, or added after eta_slab), and its line."""
    head, slab = text.split("\n[slab]", 1)
    if re.search(rf"(?m)^{key}\s*=", slab):
        slab = re.sub(rf"(?m)^{key}\s*=\s*\S+", f"{key} = {toml_value}", slab, count=1)
    else:
        slab = re.sub(r"(?m)^(eta_slab\s*=.*)$", rf"\1\n{key} = {toml_value}", slab, count=1)
    edited = head + "\n[slab]" + slab
    return edited, slab_line(edited, key)


def test_slab_keys_are_the_fields_of_a_slab():
    """[slab] holds every field of st.Slab once; what the Slab defaults (but eta_slab) is optional."""
    fields = dataclasses.fields(st.Slab)
    assert sorted(SLAB_KEYS + SLAB_OPTIONAL_KEYS) == sorted(f.name for f in fields)
    defaulted = {f.name for f in fields if f.default is not dataclasses.MISSING}
    assert set(SLAB_OPTIONAL_KEYS) == defaulted - {"eta_slab"}  # a file states its slab's loss factor


SLAB_BAD = {**{key: [v for values in BAD_VALUES.values() for v in values]
               for key in ("length", "E", "I", "mass_per_length", "support_stiffness", "eta_support", "eta_slab",
                           "shear_stiffness", "rotary_inertia")},
            "fasteners": [0, -3, 10.0, 201, True, "x"],
            "cut": ["middle", "Joint", 0, 10, 2.5, True]}


@pytest.mark.parametrize("key", sorted(SLAB_BAD))
def test_a_slab_table_refuses_what_a_slab_refuses(tmp_path, key):
    """For every [slab] key and bad value: the Slab's own message, located at that key's line in [slab]."""
    text = example_path("floating-slab").read_text()
    slab = example_track("floating-slab").slab
    refused_values = 0
    for value in SLAB_BAD[key]:
        try:
            dataclasses.replace(slab, **{key: value})
        except (TypeError, ValueError) as err:
            expected = str(err)
        else:
            continue  # allowed for this field (e.g. eta_slab = 0)
        refused_values += 1
        toml_value = {True: "true"}.get(value, json.dumps(value) if isinstance(value, str) else repr(value))
        edited, line = with_slab_value(text, key, toml_value)
        path = tmp_path / "t.toml"
        path.write_text(edited)
        with pytest.raises(TrackFileError) as caught:
            load_track_toml(path)
        assert str(caught.value) == f"{path}, line {line}: [slab] {expected}"
    assert refused_values >= 4


def test_the_slab_and_rail_share_key_names_but_not_lines(tmp_path):
    """A bad E in [slab] is located in [slab], not at the rail's E three tables up."""
    text = example_path("mortar-slab").read_text()
    edited, line = with_slab_value(text, "E", '"36 GPa"')
    rail_line = next(n for n, ln in enumerate(text.splitlines(), 1) if ln.startswith("E ="))
    assert line > rail_line
    path = tmp_path / "t.toml"
    path.write_text(edited)
    with pytest.raises(TrackFileError, match=rf"line {line}: \[slab\] E must be a real number, got '36 GPa'"):
        load_track_toml(path)


@pytest.mark.parametrize("edit,where,message", [
    # structure: unknown and missing keys, the table itself
    (lambda t: t.replace("eta_slab = 0.02", "eta_slab = 0.02\nwidth = 2.55"), "width",
     "unknown key 'width' in [slab]; allowed: length, fasteners, E, I, mass_per_length, support_stiffness, "
     "eta_support, eta_slab, and optionally shear_stiffness, rotary_inertia, cut"),
    (lambda t: re.sub(r"(?m)^eta_support\s*=.*\n", "", t), "[slab]", "missing key 'eta_support' in [slab]"),
    (lambda t: re.sub(r"(?m)^eta_slab\s*=.*\n", "", t), "[slab]", "missing key 'eta_slab' in [slab]"),
    (lambda t: t.split("\n[slab]")[0].replace("[rail]", "slab = 3\n[rail]"), "slab",
     "slab must be a table [slab], got 3"),
    (lambda t: t.replace('type = "slab"', 'type = "ballasted"') + "\n[ballast]\nsleeper_mass = 150.0\nkb = 1e8\n"
     "eta_ballast = 0.3\n", "[slab]", 'a [slab] section (a flexible slab under the pads) needs type = "slab"'),
    # rules between the slab and the track: the Track's, at the [slab] header
    (lambda t: re.sub(r"(?m)^length\s*=.*$", "length = 7.0", t), "[slab]",
     "[slab] a slab of length 7.0 m cannot carry 10 fasteners at spacing 0.65 m centred on it"),
    (lambda t: re.sub(r"(?m)^spacing\s*=.*$", "spacing = 0.6", t), "[slab]",
     "[slab] a slab of length 6.45 m cannot carry 10 fasteners at spacing 0.6 m"),
    # rules between the slab's own fields: the Slab's, at the key its message names
    (lambda t: re.sub(r"(?m)^fasteners\s*=.*$", "fasteners = 9", re.sub(r"(?m)^length\s*=.*$", "length = 5.85", t))
     .replace('cut = "joint"', 'cut = "centre"'), "cut", "[slab] cut='centre' needs an even number of fasteners"),
], ids=["unknown-key", "missing-eta_support", "missing-eta_slab", "not-a-table", "ballasted", "too-long",
        "spacing", "centre-odd"])
def test_slab_table_structure_and_cross_rules(tmp_path, edit, where, message):
    text = edit(example_path("floating-slab").read_text())
    line = (slab_line(text, where) if "\n[slab]" in text and where != "slab" else
            next(n for n, ln in enumerate(text.splitlines(), 1) if re.match(rf"{where}\s*=", ln)))
    path = tmp_path / "t.toml"
    path.write_text(text)
    with pytest.raises(TrackFileError) as caught:
        load_track_toml(path)
    assert str(caught.value).startswith(f"{path}, line {line}: {message}"), str(caught.value)


TIMOSHENKO = st.Slab(length=5.7, fasteners=9, E=3.45e10, I=1 / 3 * 1e-3, mass_per_length=700.1,
                     support_stiffness=1.234567891234e9, eta_support=0.12, eta_slab=0.0,
                     shear_stiffness=0.85 * 1.275 * 0.2 * 1.5e10, rotary_inertia=2500 * 1 / 3 * 1e-3, cut=4)


@pytest.mark.parametrize("track", [
    example_track("mortar-slab"),
    example_track("floating-slab").replace(slab=dataclasses.replace(example_track("floating-slab").slab, cut="centre"),
                                           name='floating "centre" \\ cut'),
    st.slab_track(slab=TIMOSHENKO, kv=1e8 / 3, name="Timoshenko slab"),
], ids=["mortar", "centre-cut", "timoshenko-k4"])
def test_flexible_slab_round_trips_exactly(tmp_path, track):
    """track_to_toml then load_track_toml gives the same Track, every float to the last bit."""
    text = track_to_toml(track)
    path = tmp_path / "t.toml"
    path.write_text(text)
    loaded = load_track_toml(path)
    assert loaded == track and loaded.slab == track.slab
    # Only what differs from the Slab's defaults is written among the optional keys.
    written = set(re.findall(r"(?m)^(\w+) =", text.split("[slab]")[1]))
    expected = {k for k in SLAB_OPTIONAL_KEYS if getattr(track.slab, k) != getattr(st.Slab, k, None)}
    assert written == set(SLAB_KEYS) | expected


def test_rigid_tracks_are_written_without_a_slab_table():
    assert "[slab]" not in track_to_toml(st.slab_track()) and "[slab]" not in track_to_toml(st.ballasted_track())


# The two designs as /tmp/common.md's brief derives them (per rail = half of a 2.55 m wide slab):
HALF_WIDTH = 2.55 / 2   # m
RHO_CONCRETE = 2500.0   # kg/m^3
DESIGNS = {  # thickness (m), support stiffness from the layer (N/m^2), loss factors of layer and slab
    "mortar-slab": (0.20, 3e8 * HALF_WIDTH / 0.05, 0.1, 0.02),       # CA mortar 50 mm thick, E ~ 300 MPa
    "floating-slab": (0.30, 0.02e9 * HALF_WIDTH, 0.15, 0.02),        # slab mat 0.02 N/mm^3 = 2e7 N/m^3
}
STATED = {  # the values stated in the brief, to the digits it states them
    "mortar-slab": {"I": 8.5e-4, "mass_per_length": 637.5, "support_stiffness": 7.65e9},
    "floating-slab": {"I": 2.869e-3, "mass_per_length": 956.25, "support_stiffness": 2.55e7},
}


@pytest.mark.parametrize("name", sorted(DESIGNS))
def test_slab_examples_are_the_designs_from_their_geometry(name):
    """Each example's slab is its geometry and materials, and its rail and pads are the paper's Table 2."""
    h, k, eta_support, eta_slab = DESIGNS[name]
    track = example_track(name)
    expected = st.Slab(length=6.45, fasteners=10, E=3.6e10, I=HALF_WIDTH * h**3 / 12,
                       mass_per_length=RHO_CONCRETE * HALF_WIDTH * h, support_stiffness=k,
                       eta_support=eta_support, eta_slab=eta_slab)
    for key in SLAB_KEYS + SLAB_OPTIONAL_KEYS:  # floats to rounding (1e-12): the file writes decimals
        value = getattr(expected, key)
        assert getattr(track.slab, key) == (pytest.approx(value, rel=1e-12, abs=0) if isinstance(value, float)
                                            else value), key
    for key, value in STATED[name].items():  # the brief rounds I of the floating slab to 4 digits
        assert getattr(track.slab, key) == pytest.approx(value, rel=2e-4), key
    assert track.replace(slab=None, name="x") == st.slab_track(name="x")
    assert example_track(name) == load_track_toml(example_path(name))


def test_floating_slab_bounces_at_26_hz():
    """The brief's free-slab bounce: sqrt(k / m) / 2 pi on the mat, computed here from the file's values."""
    slab = example_track("floating-slab").slab
    bounce = np.sqrt(slab.support_stiffness / slab.mass_per_length) / (2 * np.pi)
    assert bounce == pytest.approx(26.0, abs=0.05)  # measured 25.99 Hz
    assert slab.natural_frequencies(1)[0] == pytest.approx(bounce, rel=1e-12)


@pytest.mark.parametrize("name", ["mortar-slab", "floating-slab"])
def test_slab_example_values_carry_their_units(name):
    """Each [slab] value's comment ends with its unit, the unit the package states for that field."""
    units = {key: unit for key, _, _, unit in SLAB_PARAMETER_INFO}
    text = example_path(name).read_text().split("\n[slab]", 1)[1]
    for key in SLAB_KEYS:
        line = next(ln for ln in text.splitlines() if re.match(rf"{key}\s*=", ln))
        assert line.split("#", 1)[1].rstrip().endswith(f", {units[key]}"), line


def test_example_track_names_every_example():
    for name in EXAMPLES:
        assert example_track(name) == load_track_toml(example_path(name))
    with pytest.raises(ValueError, match=r"name must be one of \('slab', 'ballasted', 'mortar-slab', "
                                         r"'floating-slab'\), got 'tram'"):
        example_track("tram")
