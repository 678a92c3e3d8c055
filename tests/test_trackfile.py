"""Track files apply the Track's own rules: one rule table, located messages."""

import re

import pytest

import semitrack as st
from semitrack.model.trackfile import SECTIONS, TrackFileError, example_path, load_track_toml
from semitrack.model.tracks import FIELD_RULES

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
    from semitrack.model.trackfile import track_to_toml

    viscous = st.ballasted_track(damping="viscous")
    path = tmp_path / "viscous.toml"
    path.write_text(track_to_toml(viscous))
    assert load_track_toml(path) == viscous
    assert "damping" not in track_to_toml(st.ballasted_track())  # the paper's files stay as they are
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
