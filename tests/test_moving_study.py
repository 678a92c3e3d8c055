"""The moving chapter's comparisons side by side (:func:`semitrack.paper.moving_study.compare_cases`)."""

from __future__ import annotations

import numpy as np
import pytest

import semitrack as st
from semitrack.paper import moving_study as study

SLAB = st.slab_track(damping="viscous")
DT = 1e-4  # s: 72 steps per spacing at 300 km/h, a set-up of about a second


@pytest.fixture(scope="module")
def boundary():
    return st.fit_boundary(SLAB, n_poles=24)


@pytest.fixture(scope="module")
def side_by_side(boundary):
    cases = {"bogie": (SLAB, boundary, st.Bogie(), 300.0, DT), "one wheel": (SLAB, boundary, st.Wheel(), 300.0, DT)}
    return study.compare_cases(cases, 0.15, shares={"one wheel": "bogie"}, numpy_duration=0.03)


def test_cases_side_by_side_are_each_case_alone_bit_for_bit(boundary, side_by_side):
    alone = study.compare_runs("bogie", SLAB, boundary, st.Bogie(), 300.0, DT, 0.15, numpy_duration=0.03)
    both = side_by_side["bogie"]
    assert np.array_equal(both.green.force, alone.green.force)
    assert np.array_equal(both.truncated.force, alone.truncated.force)
    assert np.array_equal(both.kernels.loop, alone.kernels.loop)
    assert both.truncated_dofs == alone.truncated_dofs


def test_a_case_that_shares_reads_the_other_s_kernels_untimed(side_by_side):
    wheel, bogie = side_by_side["one wheel"], side_by_side["bogie"]
    assert list(side_by_side) == ["bogie", "one wheel"]  # the order asked, not the order computed
    assert wheel.kernels is bogie.kernels and np.isnan(wheel.setup) and np.isnan(wheel.from_cache)
    assert bogie.setup > 0 and bogie.from_cache > 0 and bogie.truncated_time > 0
    rows = study.moving_table(side_by_side)
    assert (rows["rms difference (%)"] < 0.05).all()  # both routes, every wheel


@pytest.mark.parametrize("shares", [{"one wheel": "trailer"}, {"lorry": "bogie"},
                                    {"one wheel": "bogie", "bogie": "one wheel"}])
def test_shares_must_name_cases_that_compute_their_own_kernels(boundary, shares):
    cases = {"bogie": (SLAB, boundary, st.Bogie(), 300.0, DT), "one wheel": (SLAB, boundary, st.Wheel(), 300.0, DT)}
    with pytest.raises(st.BadInput, match="shares must map a case to another case"):
        study.compare_cases(cases, 0.05, shares=shares)


def test_an_agreement_needs_steps_to_compare(side_by_side):
    run = side_by_side["bogie"]
    with pytest.raises(st.BadInput, match="after=0.2 s leaves fewer than two steps"):
        study.force_agreement(run.green, run.truncated, after=0.2)


def test_a_case_that_fails_fails_its_readers_too_and_nothing_waits(boundary, monkeypatch):
    import threading

    from semitrack.base import parallel
    monkeypatch.setattr(parallel, "available_cores", lambda: 2)  # the threaded path, whatever the machine
    cases = {"bogie": (SLAB, boundary, st.Bogie(), 300.0, -DT), "one wheel": (SLAB, boundary, st.Wheel(), 300.0, DT)}
    outcome = []

    def run():
        try:
            study.compare_cases(cases, 0.15, shares={"one wheel": "bogie"})
        except st.BadInput as err:
            outcome.append(err)

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(timeout=60)
    assert not worker.is_alive(), "the reader waited for kernels that never came"
    assert outcome and "dt" in str(outcome[0])


def test_a_reader_starts_once_the_kernels_are_there_not_after_the_source_s_runs(boundary, monkeypatch):
    from semitrack.base import parallel
    monkeypatch.setattr(parallel, "available_cores", lambda: 2)
    truncated, readers = study.wheel_rail_response, []

    def failing_for_the_bogie(model, vehicle, *args, **kwargs):
        if len(vehicle.wheels) > 1:
            raise RuntimeError("the bogie's truncated run")
        readers.append(truncated(model, vehicle, *args, **kwargs))
        return readers[-1]

    monkeypatch.setattr(study, "wheel_rail_response", failing_for_the_bogie)
    cases = {"bogie": (SLAB, boundary, st.Bogie(), 300.0, DT), "one wheel": (SLAB, boundary, st.Wheel(), 300.0, DT)}
    with pytest.raises(RuntimeError, match="the bogie's truncated run"):
        study.compare_cases(cases, 0.05, shares={"one wheel": "bogie"})
    assert len(readers) == 1  # the reader had the kernels before its source failed after them


@pytest.mark.parametrize("case", ["bogie", "one wheel"])
def test_the_finer_mesh_run_is_the_truncated_run_s_case(boundary, side_by_side, case):
    run = side_by_side[case]
    fine = study.finer_mesh_run(run, boundary)
    truncated = run.truncated
    assert np.array_equal(fine.t, truncated.t) and np.array_equal(fine.x, truncated.x)  # every wheel, every step
    assert fine.vehicle.offsets.tolist() == truncated.vehicle.offsets.tolist()
    assert np.array_equal(fine.roughness, truncated.roughness) and fine.ramp == truncated.ramp  # the same rail


def test_the_finer_mesh_run_is_the_green_route_on_that_mesh(boundary, side_by_side):
    run = side_by_side["one wheel"]
    fine = study.finer_mesh_run(run, boundary)
    ne = run.kernels.elements_per_bay
    green = st.moving_green_response(SLAB, st.Wheel(), study.rolling_roughness(run.green.speed),
                                     x=float(run.green.x[0]), speed=run.green.speed, dt=DT, duration=0.15,
                                     elements_per_bay=2 * ne)
    assert study.force_agreement(green, fine, after=0.05)["rms"] < 5e-4  # the two routes on the finer mesh
    assert study.force_agreement(run.truncated, fine, after=0.05)["rms"] > 2e-3  # and the mesh moves it more


@pytest.mark.parametrize("factor", [1, 9, 2.5, "2", np.nan])
def test_the_finer_mesh_factor_is_a_whole_number_from_2_to_8(boundary, side_by_side, factor):
    with pytest.raises(st.BadInput, match="factor"):
        study.finer_mesh_run(side_by_side["one wheel"], boundary, factor)


def test_the_finer_mesh_run_takes_a_comparison(boundary):
    with pytest.raises(st.BadInput, match="comparison must be a Comparison"):
        study.finer_mesh_run({"green": None}, boundary)


@pytest.mark.filterwarnings("ignore:tail_start=")  # at full rank the FFTs cost more than they save: warned of
def test_the_tail_run_is_the_comparison_s_run_at_full_rank(side_by_side):
    """At the rank of the load's phases the tail is the kernels: the comparison's own run to round-off (its
    vehicle, start, speed, step and roughness); at rank 4 past 0.05 s close, and the table says so."""
    run = side_by_side["bogie"]
    P = run.kernels.grid.positions
    full = study.tail_run(run, tail_rank=P, tail_start=0.05)
    assert np.array_equal(full.t, run.green.t) and np.array_equal(full.x, run.green.x)
    assert np.abs(full.force - run.green.force).max() <= 1e-9 * np.ptp(run.green.force)
    table = study.tail_table(side_by_side, ["bogie", "one wheel"], tail_rank=P, tail_start=0.05)
    assert (table["rms from the whole kernels (%)"] < 1e-7).all()
    def routes(c):  # the comparison's own agreement, its worst wheel
        wheels = range(len(c.green.wheels))
        return 100 * max(study.force_agreement(c.green, c.truncated, wheel=i)["rms"] for i in wheels)

    expected = [routes(side_by_side[c]) for c in ("bogie", "one wheel")]
    assert np.allclose(table["rms from the truncated model (%)"], expected, rtol=1e-4)


def test_the_tail_run_takes_a_comparison():
    with pytest.raises(st.BadInput, match="comparison must be a Comparison"):
        study.tail_run({"green": None})


def test_a_short_record_s_agreement_leaves_out_the_bands_it_cannot_resolve(side_by_side):
    """0.05 s after 0.1 s: the 50-Hz band holds no frequency of it, so it is left out (it read 0/0, NaN, and made the
    worst band NaN); the bands kept are named and every figure is finite."""
    run = side_by_side["bogie"]
    a = study.force_agreement(run.green, run.truncated, after=0.1)
    assert a["centres"][0] > 50 and a["centres"].size == a["level_difference"].size
    assert np.isfinite(a["worst_level_difference"]) and np.isfinite(a["worst_error_level"])
    with pytest.raises(st.BadInput, match="holds no frequency"):
        study.force_agreement(run.green, run.truncated, after=0.1, band=(50.0, 50.0))
