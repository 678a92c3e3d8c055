"""The naming rule of CONTRIBUTING.md: every public parameter is in its vocabulary, and the old names still work.

The vocabulary is read from CONTRIBUTING.md itself (its table's first column and the list of the
records' attributes), so that the page and this test cannot drift: a parameter outside it fails
here, and so does a vocabulary entry that no signature uses any more. The retired names are
called as a user of 0.1 would, each with the :class:`DeprecationWarning` that names the new one.
"""

from __future__ import annotations

import inspect
import pathlib
import re
import warnings

import numpy as np
import pytest

import semitrack as st
from semitrack.fe import timedomain, truncation

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGE = (ROOT / "CONTRIBUTING.md").read_text()


def _vocabulary() -> set[str]:
    table = PAGE[PAGE.index("## Vocabulary"):PAGE.index("## Retired names")]
    names = set()
    for line in table.splitlines():
        if line.startswith("| `"):
            names.update(re.findall(r"`([A-Za-z_][A-Za-z_0-9]*)`", line.split(" | ")[0]))
    records = table[table.index("Records hold"):]
    names.update(re.findall(r"`([A-Za-z_][A-Za-z_0-9]*)`", records))
    return names


def _public_callables():
    """(where, callable) of the flat API (functions, classes, their public methods) and the time-domain helpers."""
    for name in st.__all__:
        obj = getattr(st, name)
        if inspect.isclass(obj):
            yield name, obj
            for attr in dir(obj):
                member = inspect.getattr_static(obj, attr)
                if not attr.startswith("_") and (inspect.isfunction(member) or
                                                 isinstance(member, (staticmethod, classmethod))):
                    yield f"{name}.{attr}", getattr(obj, attr)
        elif callable(obj):
            yield name, obj
    for module in (timedomain, truncation):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj):
                yield f"{module.__name__}.{name}", obj


def _parameters() -> dict[str, set[str]]:
    used: dict[str, set[str]] = {}
    for where, obj in _public_callables():
        try:
            signature = inspect.signature(obj)
        except (TypeError, ValueError):  # a builtin without a signature
            continue
        for p in signature.parameters.values():
            if p.name not in ("self", "cls") and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                used.setdefault(p.name, set()).add(where)
    return used


def test_every_public_parameter_is_in_the_vocabulary():
    outside = {name: sorted(where) for name, where in _parameters().items() if name not in _vocabulary()}
    assert not outside, f"parameters outside CONTRIBUTING.md's vocabulary (add them with their meaning): {outside}"


def test_the_vocabulary_holds_no_name_that_is_not_used():
    stale = _vocabulary() - set(_parameters())
    assert not stale, f"CONTRIBUTING.md lists names no public signature uses: {sorted(stale)}"


def test_no_signature_uses_a_retired_name():
    retired = PAGE[PAGE.index("## Retired names"):]
    used = _parameters()
    for line in retired.splitlines()[4:]:
        old, new, where = (cell.strip() for cell in line.strip("| ").split(" | "))
        for name in set(re.findall(r"`([a-z_]+)`", old)) - set(re.findall(r"`([a-z_]+)`", new)):
            assert not (used.get(name, set()) & set(re.findall(r"`([A-Za-z_.]+)`", where))), (name, where)


# ------------------------------------------------------------------------------------------------
# The old names, as 0.1 took them: each warns, naming the new one, and gives what the new one gives
# ------------------------------------------------------------------------------------------------
def _old(call, old: str, new: str):
    """``call()``, which must warn that ``old`` is renamed ``new`` (other old names in it may warn too)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = call()
    messages = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]
    assert any(f"'{old}' is renamed '{new}'" in m for m in messages), messages
    return out


@pytest.fixture(scope="module")
def model():
    return st.TruncatedTrack(st.slab_track(damping="viscous"), 2, elements_per_bay=4)


def test_the_routes_take_their_old_keywords(model):
    new = st.wheel_rail_response(model, st.Wheel(), x=0.1, dt=5e-5, duration=0.03)
    old = _old(lambda: st.wheel_rail_response(model=model, wheel=st.Wheel(), x_contact=0.1, dt=5e-5, duration=0.03),
               "x_contact", "x")
    np.testing.assert_array_equal(old.force, new.force)
    _old(lambda: st.wheel_rail_response(model=model, wheel=st.Wheel(), dt=5e-5, duration=0.03), "model", "track")
    with pytest.raises(TypeError, match="both 'x_contact' and 'x'"):
        st.wheel_rail_response(model, st.Wheel(), x=0.1, x_contact=0.1)
    conv = _old(lambda: st.convolution_response(st.slab_track(damping="viscous"), st.Wheel(), x_contact=0.1,
                                                dt=1e-4, duration=0.03, memory=0.02), "x_contact", "x")
    np.testing.assert_allclose(conv.x, 0.1)


def test_the_fe_helpers_take_their_old_keywords(model):
    new = timedomain.pulse_response(model, x=(0.0,), dt=5e-5, duration=0.005)
    old = _old(lambda: timedomain.pulse_response(model=model, positions=(0.0,), dt=5e-5, duration=0.005),
               "positions", "x")
    np.testing.assert_array_equal(old.u, new.u)
    _old(lambda: timedomain.pulse_response(model, (0.0,), dt=5e-5, t_end=0.005), "t_end", "duration")
    _old(lambda: timedomain.moving_load_response(model, positions=(0.0,), x_start=-0.5, x_end=0.5, dt=1e-4),
         "positions", "x")
    np.testing.assert_array_equal(_old(lambda: model.output_matrix(positions=[0.1]), "positions", "x").toarray(),
                                  model.output_matrix([0.1]).toarray())
    _old(lambda: model.points(positions=[0.1]), "positions", "x")
    _old(lambda: model.local_flexibility(positions=[0.1]), "positions", "x")
    study = truncation.truncation_study(st.slab_track(), [50.0, 100.0], n_bays=(1, 2), elements_per_bay=4)
    assert _old(lambda: truncation.bays_needed(study, maximum=0.5), "maximum", "max_error").equals(
        truncation.bays_needed(study, max_error=0.5))


def test_fetrack_takes_its_old_end_and_track_keywords():
    slab, ballast = st.slab_track(), st.ballasted_track()
    new = st.FETrack(slab, 1, 1, left_end="free", right_end="pinned", elements_per_bay=4)
    old = _old(lambda: st.FETrack(slab, 1, 1, left="free", right="pinned", elements_per_bay=4), "left", "left_end")
    assert (old.left_end, old.right_end) == (new.left_end, new.right_end) == ("free", "pinned")
    assert _old(lambda: new.right, "right", "right_end") == "pinned"
    moved = _old(lambda: st.FETrack(slab, 2, 2, right_track=ballast, transition=0, elements_per_bay=4),
                 "right_track", "right")
    assert moved.right_track is not None and moved.right_track.name == ballast.name
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the new keyword takes a track without a word
        assert st.FETrack(slab, 2, 2, right=ballast, transition=0, elements_per_bay=4).right_track.name == ballast.name


def test_the_records_keep_their_old_attributes():
    bnd = st.fit_boundary(st.slab_track(damping="viscous"), band=(3, 300), n_poles=4)
    assert _old(lambda: bnd.model, "model", "rational") is bnd.rational
    mck = _old(lambda: bnd.second_order(), "second_order", "matrix_system")
    np.testing.assert_array_equal(mck.matrices()[2], bnd.matrix_system().matrices()[2])
    tdr = st.track_decay_rate(st.slab_track(), band=(500, 500), df=50.0)
    np.testing.assert_array_equal(_old(lambda: tdr.positions, "positions", "distances"), tdr.distances)
    old = _old(lambda: st.track_decay_rate(st.slab_track(), bands=(500, 500), df=50.0, x_load=0.0), "bands", "band")
    np.testing.assert_array_equal(old.decay_rate, tdr.decay_rate)


def test_the_other_old_keywords(tmp_path):
    curve = _old(lambda: st.FrequencyFunction(lambda f: 1e8 + 0 * f, kind="stiffness"), "kind", "quantity")
    assert curve.quantity == curve.kind == "stiffness"
    assert _old(lambda: st.InfiniteTrack(st.slab_track()).support_position(k=2), "k", "support") == 2.5 * 0.65
    path = _old(lambda: st.export_system(st.paper_table4(), tmp_path / "t4.json", band_hz=(3, 900)), "band_hz", "band")
    assert '"band_hz": [\n' in path.read_text() or '"band_hz": [3' in path.read_text()


def test_a_left_out_origin_warns_that_x_is_now_from_a_mid_span():
    track, f = st.slab_track(), [100.0, 945.0]
    with pytest.warns(FutureWarning, match="x is measured from a mid-span since semitrack 0.2"):
        left_out = st.point_receptance(track, f, 0.1)
    np.testing.assert_array_equal(left_out, st.point_receptance(track, f, 0.1, origin="midspan"))
    # the two origins are d/2 apart, and the mid-span one agrees with the exact infinite track at any x
    np.testing.assert_allclose(st.point_receptance(track, f, 0.1, origin="midspan"),
                               st.point_receptance(track, f, 0.1 + track.spacing / 2, origin="support"), rtol=1e-12)
    inf = st.InfiniteTrack(track)
    np.testing.assert_allclose(st.point_receptance(track, f, 0.1, origin="midspan"),
                               inf.receptance(f, 0.1, [0.1])[:, 0], rtol=1e-10)
    with pytest.warns(FutureWarning):
        st.wheel_rail_force(track, f, st.Wheel())
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # on an InfiniteTrack x always was from the mid-span: no warning
        st.wheel_rail_force(inf, f, st.Wheel(), 0.1)
    np.testing.assert_allclose(st.wheel_rail_force(track, f, st.Bogie(), 0.1, origin="midspan"),
                               st.wheel_rail_force(inf, f, st.Bogie(), 0.1), rtol=1e-10)
    with pytest.raises(ValueError, match="origin must be one of"):
        st.point_receptance(track, f, 0.1, origin="rail head")


def test_a_renamed_function_s_warnings_still_point_at_its_caller():
    """The keywords' wrapper is one more frame: the routes' own warnings count it."""
    with pytest.warns(RuntimeWarning, match="cuts off their tail") as caught:
        st.convolution_response(st.slab_track(damping="viscous"), st.Wheel(), dt=1e-4, duration=0.03, memory=0.01)
    assert pathlib.Path(caught[0].filename).name == pathlib.Path(__file__).name
