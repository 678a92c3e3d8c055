"""Progress bars (tqdm): drawn on a terminal and in a Jupyter kernel, never when quiet, redirected,
in CI or in the book's build; the package's own long work shows one, short work none."""

import io
import sys
import time
import warnings
from pathlib import Path

import pytest
from terminal import FakeTerminal

import semitrack as st
from semitrack.base import progress
from semitrack.base.progress import Progress, progress_shown, silenced


def test_a_bar_is_drawn_on_a_terminal_with_its_count_and_note(clean_environment):
    term = FakeTerminal()
    with Progress("fit", 4, stream=term, unit="start") as p:
        p.update(2, "start 2")
    out = term.getvalue()
    assert "fit:" in out and "2/4" in out and "50%" in out and "start 2" in out and "start/s" in out
    assert out.endswith("\n")


def test_a_new_stage_note_shows_at_once_without_a_step(clean_environment):
    term = FakeTerminal()
    p = Progress("run", 2, stream=term)
    p.update(0, "route window: the track is imperfect")
    assert "route window: the track is imperfect" in term.getvalue()
    p.close()


def test_advance_counts_on_and_never_passes_the_total(clean_environment):
    term = FakeTerminal()
    with Progress("kernels", 3, stream=term) as p:
        for _ in range(5):
            p.advance()
    assert "3/3" in term.getvalue() and "4/3" not in term.getvalue() and "5/3" not in term.getvalue()


def test_silent_when_quiet_redirected_in_ci_or_turned_off(clean_environment):
    term, pipe = FakeTerminal(), io.StringIO()  # a StringIO is not a terminal, like a file or a pipe
    Progress("fit", 4, quiet=True, stream=term).update(1)
    with Progress("fit", 4, stream=pipe) as p:
        p.update(1)
    assert term.getvalue() == "" and pipe.getvalue() == ""
    for name, value in (("CI", "true"), ("SEMITRACK_PROGRESS", "0"), ("SEMITRACK_PROGRESS", "off")):
        with pytest.MonkeyPatch.context() as mp:
            mp.setenv(name, value)
            with Progress("fit", 4, stream=term) as p:
                p.update(1)
            assert term.getvalue() == "", (name, value)


def test_forced_on_where_the_stream_is_not_a_terminal(clean_environment):
    clean_environment.setenv("SEMITRACK_PROGRESS", "1")
    pipe = io.StringIO()
    with Progress("fit", 2, stream=pipe) as p:
        p.update(2)
    assert "2/2" in pipe.getvalue()
    assert not progress_shown(pipe, quiet=True)  # --quiet wins over the variable
    clean_environment.setenv("CI", "1")
    assert progress_shown(pipe)  # an explicit request wins over CI


def test_an_unknown_setting_warns_once_and_follows_the_terminal(clean_environment):
    clean_environment.setenv("SEMITRACK_PROGRESS", "sometimes")
    progress._warned_values.discard("sometimes")
    with pytest.warns(UserWarning, match="SEMITRACK_PROGRESS='sometimes'"):
        assert progress_shown(FakeTerminal())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert not progress_shown(io.StringIO())


def test_a_jupyter_kernel_stream_counts_as_watched(clean_environment):
    kernel_stream = type("OutStream", (io.StringIO,), {"__module__": "ipykernel.iostream"})()
    assert progress_shown(kernel_stream)


def test_library_bars_wait_a_second_so_short_work_draws_nothing(clean_environment):
    term = FakeTerminal()
    with Progress("moving kernels", 10, stream=term, delay=progress.LIBRARY_DELAY) as p:
        p.update(5)
    assert term.getvalue() == ""
    with Progress("moving kernels", 10, stream=term, delay=0.05) as p:
        time.sleep(0.1)
        p.update(5)
    assert "5/10" in term.getvalue()


def test_the_kernel_set_up_reports_its_frequency_blocks(clean_environment, monkeypatch):
    """The moving Green's functions' set-up, the long work a user waits for, draws a bar of blocks."""
    from semitrack.fe import kernels

    term = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", term)
    monkeypatch.setattr(kernels, "LIBRARY_DELAY", 0.0)
    track = st.ballasted_track(damping="viscous")
    grid = kernels.grid_of(track, 40.0, 1e-4)
    kernels.moving_kernels(track, 4, grid, 200)
    out = term.getvalue()
    blocks = -(-kernels.ALIAS_FACTOR * 100 // kernels.FREQUENCY_BLOCK)  # A L / 2 frequencies
    assert "moving kernels" in out and f"{blocks}/{blocks}" in out and "block" in out


def test_fits_and_a_window_run_report_their_starts_and_steps(clean_environment, monkeypatch):
    """The other long work: a broadband end's fit by start, an equivalent system's by run, a window by step."""
    import semitrack.boundary.fitting as boundary_fitting
    import semitrack.equivalent.multistart as multistart
    import semitrack.interaction.window_model as window_model

    for module in (boundary_fitting, multistart, window_model):
        monkeypatch.setattr(module, "LIBRARY_DELAY", 0.0)
    term = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", term)
    st.fit_boundary(st.slab_track(damping="viscous"), band=(3, 300), n_poles=4, n_starts=1)
    assert "boundary fit" in term.getvalue() and "1/1" in term.getvalue() and "4 poles" in term.getvalue()
    term.seek(0), term.truncate()
    st.fit_equivalent(st.slab_track(), n_bars=2, band=(3, 300), n_starts=2)
    assert "equivalent fit" in term.getvalue() and "4/4" in term.getvalue()  # 2 screened, 2 refined
    term.seek(0), term.truncate()
    track = st.ballasted_track(damping="viscous")
    boundary = st.load_boundary(Path(__file__).parent / "data" / "boundary_ballasted_viscous_24.json")
    window = st.WindowTrack(track, behind=2, ahead=3, elements_per_bay=4, system=boundary)
    run = st.wheel_rail_response(window, st.Wheel(), None, x=0.0, speed=50.0, dt=1e-4, duration=0.04, ramp=0.01)
    n = run.t.size - 1
    assert "window run" in term.getvalue() and f"{n}/{n}" in term.getvalue()


def test_silenced_blocks_open_no_bar_and_a_study_silences_its_cases_work(clean_environment):
    """Inside ``silenced()`` no bar opens (the CLI's --quiet, a study's cases); a study's own line stays."""
    import study_functions as sf

    term = FakeTerminal()
    with silenced():
        with Progress("hushed", 3, stream=term) as bar:
            bar.update(3)
    assert term.getvalue() == ""
    with Progress("heard", 3, stream=term) as bar:
        bar.update(3)
    assert "heard" in term.getvalue()
    term = FakeTerminal()
    clean_environment.setattr(sys, "stderr", term)
    st.run_study(sf.with_a_bar, [{"x": 1.0}, {"x": 2.0}])
    assert "study: 100%" in term.getvalue() and "inner work" not in term.getvalue()
    with Progress("inner work", 2, stream=term) as bar:  # outside a study the same work shows its bar
        bar.update(2)
    assert "inner work" in term.getvalue()
    from semitrack.studies.runner import WORKER_ENVIRONMENT

    assert WORKER_ENVIRONMENT["SEMITRACK_PROGRESS"] == "0"  # a dask worker's bars would garble the study's line


def test_quiet_on_the_command_line_silences_the_package_s_bars_too(clean_environment, tmp_path):
    """``semitrack fit --quiet``: neither the stage bar nor the fit's own bar (by start) is drawn."""
    import semitrack.equivalent.multistart as multistart
    from semitrack.cli import main
    from semitrack.model.trackfile import track_to_toml

    clean_environment.setattr(multistart, "LIBRARY_DELAY", 0.0)
    track = tmp_path / "slab.toml"
    track.write_text(track_to_toml(st.slab_track()))
    for quiet, shown in ((False, True), (True, False)):
        term = FakeTerminal()
        clean_environment.setattr(sys, "stderr", term)
        args = ["fit", str(track), "--bars", "1", "--band", "3", "300", "-o", str(tmp_path / f"s{quiet}.json")]
        assert main(args + ["--quiet"] * quiet) == 0
        assert ("equivalent fit" in term.getvalue()) is shown, term.getvalue()


def test_a_finished_search_shows_what_it_did_as_the_whole_and_no_work_draws_no_bar(clean_environment):
    term = FakeTerminal()
    with Progress("search", 24, stream=term, unit="start") as bar:
        bar.advance(9)
        bar.finish()  # the search stopped at an early order
    assert "9/9" in term.getvalue() and "100%" in term.getvalue()
    quick = FakeTerminal()
    with Progress("quick search", 24, stream=quick, delay=60.0) as bar:  # done before its delay: silent
        bar.advance(3)
        bar.finish()
    assert quick.getvalue() == ""
    empty = FakeTerminal()
    with Progress("nothing", 0, stream=empty) as bar:
        bar.update(0, "a note")
    assert empty.getvalue() == ""
