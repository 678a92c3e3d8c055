"""Studies over many cases: the same table however they run, resumed after a kill, never trusting a bad record.

Independent checks: the serial table against a local 2-worker dask cluster's and a user's
``Client``'s, compared bit for bit (``DataFrame.equals`` and every float's bytes), with cases that
finish out of order; any row against its case run alone; a study killed with SIGKILL half way
(serially and on a cluster) rerun, the cases' own log showing which ran again; records truncated,
flipped, swapped between cases, planted as links or of another study, each recomputed; the
percentiles' bootstrap intervals against their nominal coverage on a known distribution.
"""

import contextlib
import functools
import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time
import types
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import study_functions as sf
from terminal import FakeTerminal

import semitrack as st
from semitrack.studies.cases import _digest
from semitrack.studies.statistics import exceedance, exceedance_table, percentile_table, percentiles

HERE = Path(__file__).parent
CASES = [{"x": i, "pause": 0.05 * (5 - i) if i < 5 else 0.0} for i in range(10)]  # the first cases finish last


def bits(table: pd.DataFrame) -> list:
    """Every value of the table as bytes (floats exactly) with its column's dtype."""
    return [(c, str(table[c].dtype), [np.float64(v).tobytes() if isinstance(v, float) else repr(v)
                                      for v in table[c].tolist()]) for c in table.columns]


@pytest.fixture(scope="module")
def user_client():
    from distributed import Client, LocalCluster
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                           dashboard_address="127.0.0.1:0")
    client = Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_the_table_is_the_same_bit_for_bit_serially_on_a_local_cluster_and_through_a_users_client(user_client):
    serial = st.run_study(sf.eigen, CASES, progress=False)
    local = st.run_study(sf.eigen, CASES, client=2, progress=False)
    users = st.run_study(sf.eigen, CASES, client=user_client, progress=False)
    assert serial.equals(local) and serial.equals(users)
    assert bits(serial) == bits(local) == bits(users)
    assert list(serial.columns) == ["x", "pause", "largest", "trace", "even", "pid", "error"]
    assert serial.x.tolist() == list(range(10)) and (serial.error == "").all()
    assert serial.attrs["computed"] == 10 and serial.attrs["cached"] == 0 and len(serial.attrs["seconds"]) == 10
    assert user_client.status == "running"  # a user's client is left open


def test_any_row_equals_its_case_run_alone():
    table = st.run_study(sf.eigen, CASES, progress=False)
    for i in (0, 3, 9):
        alone = st.run_study(sf.eigen, [CASES[i]], progress=False)
        assert bits(alone) == bits(table.iloc[[i]].reset_index(drop=True))


def test_a_failing_case_is_recorded_and_the_study_goes_on():
    table = st.run_study(sf.failing, [{"x": i} for i in range(6)], progress=False)
    assert table.error[1] == "ArithmeticError: case 1 fails" and table.error[3].startswith("ArithmeticError")
    assert table.error[4].startswith("func returned [4] (list), not a dict of numbers")
    assert table.error[0] == table.error[2] == ""
    assert table.x2[0] == 0.0 and table.x2[2] == 4.0 and math.isnan(table.x2[1]) and math.isnan(table.x2[4])


def test_results_that_are_not_numbers_or_clash_with_an_input_are_the_cases_errors():
    table = st.run_study(lambda x: {"x": 1.0} if x else {"y": "text"}, [{"x": 0}, {"x": 1}], progress=False)
    assert "not a number" in table.error[0] and "also an input" in table.error[1]
    table = st.run_study(lambda: {"y": np.float32(1.5), "n": np.int64(3), "b": np.bool_(True)}, [{}], progress=False)
    assert table.y[0] == 1.5 and table.n[0] == 3 and bool(table.b[0]) is True and table.b.dtype == bool


def test_a_study_resumes_from_its_records_and_computes_only_what_is_missing(tmp_path):
    log = str(tmp_path / "log")
    cases = [{"x": i, "log": log} for i in range(6)]
    first = st.run_study(sf.logged, cases[:3], cache_dir=tmp_path / "c", progress=False)
    assert sf.ran(log) == [0, 1, 2]
    again = st.run_study(sf.logged, cases, cache_dir=tmp_path / "c", progress=False)
    assert sf.ran(log) == [0, 1, 2, 3, 4, 5]
    assert again.attrs["cached"] == 3 and again.attrs["computed"] == 3
    assert bits(again.iloc[:3]) == bits(first)
    third = st.run_study(sf.logged, cases, cache_dir=tmp_path / "c", progress=False)
    assert sf.ran(log) == [0, 1, 2, 3, 4, 5] and bits(third) == bits(again)
    # another function is another study: its cases are not taken from these records
    st.run_study(_logged_again, cases[:1], cache_dir=tmp_path / "c", progress=False)
    assert sf.ran(log) == [0, 1, 2, 3, 4, 5, 0]


def _logged_again(x, log):
    return sf.logged(x, log)


def test_failed_cases_are_stored_with_their_error_and_not_run_again(tmp_path):
    cases = [{"x": i} for i in range(4)]
    first = st.run_study(sf.failing, cases, cache_dir=tmp_path, progress=False)
    again = st.run_study(sf.failing, cases, cache_dir=tmp_path, progress=False)
    assert again.attrs["cached"] == 4 and bits(first) == bits(again)


KILLED = textwrap.dedent("""
    import sys
    sys.path.insert(0, sys.argv[1])
    import semitrack as st, study_functions as sf
    if __name__ == "__main__":
        client = None if sys.argv[4] == "0" else int(sys.argv[4])
        cases = [{"x": i, "log": sys.argv[3], "pause": 0.4} for i in range(12)]
        st.run_study(sf.logged, cases, cache_dir=sys.argv[2], client=client, progress=False)
""")


@pytest.mark.parametrize("client", [0, 2], ids=["serial", "local cluster"])
def test_killed_half_way_a_rerun_computes_only_the_missing_cases_and_gives_the_same_table(tmp_path, client):
    cache, log = tmp_path / "cache", str(tmp_path / "log")
    script = tmp_path / "study.py"
    script.write_text(KILLED)
    proc = subprocess.Popen([sys.executable, str(script), str(HERE), str(cache), log, str(client)],
                            start_new_session=True, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and len(list(cache.glob("*.json"))) < 4:
            time.sleep(0.05)
            assert proc.poll() is None, "the study ended before it was killed"
        os.kill(proc.pid, signal.SIGKILL)  # the parent only: a cluster's workers must not outlive it
        proc.wait(timeout=30)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and _alive_in_group(proc.pid):
            time.sleep(0.1)
        assert not _alive_in_group(proc.pid), "workers outlived their study"
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)
    stored = len(list(cache.glob("*.json")))
    assert 4 <= stored < 12
    assert not list(cache.glob(".*.tmp"))  # the atomic write leaves whole records only
    before = sf.ran(log)
    cases = [{"x": i, "log": log, "pause": 0.4} for i in range(12)]  # the killed study's cases
    resumed = st.run_study(sf.logged, cases, cache_dir=cache, progress=False)
    rerun = sf.ran(log)[len(before):]
    assert resumed.attrs["cached"] == stored and resumed.attrs["computed"] == 12 - stored == len(rerun)
    assert (resumed.error == "").all() and resumed.y.tolist() == [i + 0.5 for i in range(12)]
    fresh = st.run_study(sf.logged, cases, progress=False)
    assert bits(fresh) == bits(resumed)


def _alive_in_group(group: int) -> bool:
    """Whether a process of the session ``group`` still runs (zombies not counted)."""
    for status in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = status.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == group and fields[0] != "Z":  # fields after the name: state, ppid, pgrp, session
            return True
    return False


def _corrupt_each_way(folder: Path, keys: list[Path]) -> None:
    text = keys[0].read_text()
    keys[0].write_text(text[: len(text) // 2])  # truncated
    data = bytearray(keys[1].read_bytes())
    data[len(data) // 2] ^= 0x20  # a flipped bit
    keys[1].write_bytes(bytes(data))
    keys[2].write_text(keys[3].read_text())  # another case's record under this case's name
    other = json.loads(keys[4].read_text())
    other["study"] = "someone.else"
    other.pop("digest")
    keys[4].write_text(json.dumps({**other, "digest": _digest(other)}))  # another study's, its digest made good
    target = folder.parent / "elsewhere.json"
    target.write_text(keys[5].read_text())
    keys[5].unlink()
    keys[5].symlink_to(target)  # a link planted in the folder
    forged = json.loads(keys[6].read_text())
    forged["result"] = {"d": {"largest": "not a number"}}
    keys[6].write_text(json.dumps(forged))  # a result that is no number
    keys[7].write_text("[" * 100_000)  # nested past the parser
    keys[8].write_text(json.dumps({**json.loads(keys[8].read_text()), "version": 99}))


def test_a_corrupted_record_is_recomputed_never_trusted(tmp_path):
    folder = tmp_path / "cache"
    cases = [{"x": i} for i in range(10)]
    clean = st.run_study(sf.eigen, cases, cache_dir=folder, progress=False)
    stem = {json.dumps(c): p for c in cases for p in folder.glob("*.json")
            if json.loads(p.read_text())["case"]["d"]["x"] == c["x"]}
    keys = [stem[json.dumps(c)] for c in cases]
    _corrupt_each_way(folder, keys)
    again = st.run_study(sf.eigen, cases, cache_dir=folder, progress=False)
    assert again.attrs["computed"] == 8 and again.attrs["cached"] == 2  # cases 3 and 9 were left whole
    assert bits(again) == bits(clean)
    assert not keys[5].is_symlink() and (tmp_path / "elsewhere.json").read_text() != ""
    third = st.run_study(sf.eigen, cases, cache_dir=folder, progress=False)
    assert third.attrs["cached"] == 10


def test_a_study_without_cases_is_an_empty_table():
    table = st.run_study(sf.eigen, [], progress=False)
    assert list(table.columns) == ["error"] and len(table) == 0


@pytest.mark.parametrize("kwargs, name", [
    (dict(func=3), "func"), (dict(cases={"x": 1}), "cases"), (dict(cases="x"), "cases"), (dict(cases=[1]), "cases"),
    (dict(cases=[{1: 2}]), r"cases\[0\]"), (dict(cases=[{"x": 1}, {"error": 2}]), r"cases\[1\]"),
    (dict(cases=[{"x": object()}]), r"cases\[0\]"), (dict(cases=[{"x y": 1}]), r"cases\[0\]"),
    (dict(client=0), "client"), (dict(client=-2), "client"), (dict(client=True), "client"),
    (dict(client=1000), "client"), (dict(client="tcp://x:8786"), "client"), (dict(client=2.0), "client"),
    (dict(progress=1), "progress"), (dict(progress="yes"), "progress"), (dict(cache_dir=""), "cache_dir"),
    (dict(cache_dir=3), "cache_dir"),
])
def test_bad_arguments_are_refused_before_any_case_runs(kwargs, name, tmp_path):
    log = str(tmp_path / "log")
    args = dict(func=sf.logged, cases=[{"x": 1, "log": log}]) | kwargs
    with pytest.raises(st.BadInput, match=name):
        st.run_study(args.pop("func"), args.pop("cases"), **args)
    assert sf.ran(log) == []


def test_a_cache_folder_that_is_a_file_is_refused_before_any_case_runs(tmp_path):
    log = str(tmp_path / "log")
    (tmp_path / "file").write_text("")
    with pytest.raises(st.BadInput, match="cache_dir"):
        st.run_study(sf.logged, [{"x": 1, "log": log}], cache_dir=tmp_path / "file")
    assert sf.ran(log) == []


def test_the_progress_line_shows_done_running_failed_and_the_time_left(clean_environment):
    term = FakeTerminal()
    clean_environment.setattr(sys, "stderr", term)
    st.run_study(sf.failing, [{"x": i} for i in range(4)])
    text = term.getvalue()
    assert "study: 100%" in text and "4/4" in text and "2 failed" in text and "s left" in text
    assert "1 running" in text and text.endswith("\n")
    quiet = FakeTerminal()
    clean_environment.setattr(sys, "stderr", quiet)
    st.run_study(sf.failing, [{"x": 0}], progress=False)
    assert quiet.getvalue() == ""
    assert st.run_study(sf.failing, [], progress=True).empty and term.getvalue() == text  # no cases: no bar


def test_blas_runs_on_one_thread_inside_each_case():
    from threadpoolctl import threadpool_info, threadpool_limits

    def threads():
        return {"blas": max([p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"] or [0])}
    with threadpool_limits(limits=2, user_api="blas"):  # the caller's BLAS on two threads
        assert threads()["blas"] == 2
        assert st.run_study(threads, [{}], progress=False).blas[0] == 1
        assert threads()["blas"] == 2  # and given back


def test_a_case_may_start_processes_on_a_local_cluster_as_it_may_here():
    serial = st.run_study(sf.spawns, [{"x": 3}], progress=False)
    local = st.run_study(sf.spawns, [{"x": 3}], client=1, progress=False)
    assert serial.error[0] == "" and bits(serial) == bits(local)


def test_more_cases_than_are_handed_out_at_once_all_run_in_order(user_client):
    cases = [{"x": i, "n": 4} for i in range(60)]  # beyond AHEAD x workers + 8 in flight
    table = st.run_study(sf.eigen, cases, client=user_client, progress=False)
    assert bits(table) == bits(st.run_study(sf.eigen, cases, progress=False))


def test_a_result_may_not_take_the_name_of_any_cases_input():
    table = st.run_study(sf.echo, [{"x": 1.0}, {"x": 2.0, "y": 5.0}], progress=False)
    assert "also an input" in table.error[0] and table.error[1] == ""
    assert table.y.tolist()[1] == 5.0 and list(table.columns) == ["x", "y", "z", "error"]


def test_with_a_cache_only_a_function_with_a_name_that_tells_it_apart_is_taken(tmp_path):
    def nested(x):
        return {"y": x}

    class Callable:
        def __call__(self, x):
            return {"y": x}

        def method(self, x):
            return {"y": x}
    for func in (lambda x: {"y": x}, nested, Callable(), Callable().method,
                 functools.partial(sf.logged, log=lambda: 0)):
        with pytest.raises(st.BadInput, match="func"):
            st.run_study(func, [{"x": 1.0}], cache_dir=tmp_path, progress=False)
        assert not list(tmp_path.glob("*.json"))  # refused before any case ran
    fine = functools.partial(sf.logged, log=str(tmp_path / "log"))
    assert st.run_study(fine, [{"x": 1}], cache_dir=tmp_path, progress=False).error[0] == ""


def test_an_edited_function_or_other_fixed_arguments_are_another_study():
    from semitrack.studies.cases import study_name
    edited = types.FunctionType(sf.failing.__code__, sf.eigen.__globals__, "eigen")
    edited.__qualname__, edited.__module__ = sf.eigen.__qualname__, sf.eigen.__module__
    assert study_name(edited) != study_name(sf.eigen) and study_name(sf.eigen) == study_name(sf.eigen)
    assert study_name(functools.partial(sf.eigen, n=3)) != study_name(functools.partial(sf.eigen, n=4))
    assert study_name(functools.partial(sf.eigen, n=3)) == study_name(functools.partial(sf.eigen, n=3))


def test_a_record_that_cannot_be_stored_is_warned_of_and_the_study_goes_on(tmp_path, monkeypatch):
    from semitrack.studies import cases as records_of_cases
    cases = [{"x": i} for i in range(3)]
    st.run_study(sf.eigen, cases[:1], cache_dir=tmp_path, progress=False)
    (stored,) = tmp_path.glob("*.json")
    name = records_of_cases.study_name(sf.eigen)
    planted = tmp_path / f"{records_of_cases.case_key(name, cases[1])}.json"
    planted.mkdir()  # something else under case 1's record name
    with pytest.warns(RuntimeWarning, match="not stored"):
        table = st.run_study(sf.eigen, cases, cache_dir=tmp_path, progress=False)
    assert (table.error == "").all() and table.attrs["cached"] == 1 and planted.is_dir()
    monkeypatch.setattr(records_of_cases, "MAX_RECORD_BYTES", 100)  # a case too large to keep
    with pytest.warns(RuntimeWarning, match="bytes"):
        st.run_study(sf.eigen, [{"x": 7}], cache_dir=tmp_path / "small", progress=False)
    assert not list((tmp_path / "small").glob("*.json")) and stored.exists()


# --- statistics ----------------------------------------------------------------------------------------
def test_percentile_intervals_cover_the_true_percentile_at_about_their_level():
    rng = np.random.default_rng(0)
    true = {50: 0.0, 90: 1.2815515655446004}
    hits = {50: 0, 90: 0}
    trials = 300
    for _ in range(trials):
        t = percentiles(rng.standard_normal(200), [50, 90], confidence=0.9, n_boot=400, seed=int(rng.integers(1e9)))
        for q, v in true.items():
            row = t[t.q == q].iloc[0]
            hits[q] += row.low <= v <= row.high
    for q in hits:  # 90 % nominal; the percentile bootstrap is a little narrow at n = 200
        assert 0.80 < hits[q] / trials < 0.97, (q, hits[q] / trials)


def test_percentiles_are_reproducible_and_leave_out_failed_cases():
    values = np.r_[np.arange(1.0, 101.0), np.nan]
    a, b = percentiles(values, seed=3), percentiles(values, seed=3)
    assert a.equals(b) and a.n[0] == 100
    np.testing.assert_allclose(a.value, np.percentile(np.arange(1.0, 101.0), [50, 95, 99]))
    assert (a.low <= a.value).all() and (a.value <= a.high).all()
    big = percentiles(np.random.default_rng(1).standard_normal(3_000_000), [50], n_boot=100)
    assert abs(big.value[0]) < 0.01 and big.high[0] - big.low[0] < 0.01


def test_exceedance_uses_weibull_positions_and_groups_by_an_input():
    e = exceedance([3.0, 1.0, 2.0, np.nan])
    assert e.value.tolist() == [1.0, 2.0, 3.0] and e.exceedance.tolist() == [0.75, 0.5, 0.25]
    table = pd.DataFrame({"v": [0, 0, 1, 1, 1], "F": [1.0, 2.0, 3.0, 4.0, 5.0]})
    grouped = exceedance_table(table, "F", "v")
    assert grouped.v.tolist() == [0, 0, 1, 1, 1] and grouped.exceedance.tolist()[:2] == pytest.approx([2 / 3, 1 / 3])
    p = percentile_table(table, "F", "v", [50])
    assert p.v.tolist() == [0, 1] and p.value.tolist() == [1.5, 4.0]


@pytest.mark.parametrize("call, name", [
    (lambda: percentiles([]), "values"), (lambda: percentiles([np.nan]), "values"),
    (lambda: percentiles("1"), "values"), (lambda: percentiles([[1.0]]), "values"),
    (lambda: percentiles([1.0, np.inf]), "values"), (lambda: percentiles([1.0], [101]), "q"),
    (lambda: percentiles([1.0], "50"), "q"), (lambda: percentiles([1.0], []), "q"),
    (lambda: percentiles([1.0], confidence=1.0), "confidence"), (lambda: percentiles([1.0], n_boot=10), "n_boot"),
    (lambda: percentiles([1.0], n_boot=10**6), "n_boot"), (lambda: percentiles([1.0], seed=-1), "seed"),
    (lambda: percentile_table(pd.DataFrame({"a": [1.0]}), "b"), "column"),
    (lambda: percentile_table(pd.DataFrame({"a": [1.0]}), "a", "c"), "by"),
    (lambda: percentile_table({"a": [1.0]}, "a"), "table"),
    (lambda: percentiles(np.ones(10_000), [50], n_boot=100_000), "n_boot"),
    (lambda: percentiles([1.0], list(range(101))), "q"),
    (lambda: percentile_table(pd.DataFrame({"v": [0, 1], "F": [1.0, np.nan]}), "F", "v"), "v = 1"),
])
def test_statistics_refuse_what_they_cannot_summarise(call, name):
    with pytest.raises(st.BadInput, match=name):
        call()


def test_masked_values_and_nan_groups_are_not_lost_or_counted_silently():
    assert percentiles(np.ma.masked_array([1.0, 2.0, 3.0], [0, 1, 0]), [50]).n[0] == 2
    table = pd.DataFrame({"v": [0.0, 0.0, np.nan], "F": [1.0, 2.0, 3.0]})
    groups = percentile_table(table, "F", "v", [50])
    assert len(groups) == 2 and groups.n.tolist() == [2, 1]


def test_the_figures_draw_a_studys_table():
    from semitrack.plotting import exceedance_figure, percentile_figure, scatter_figure
    rng = np.random.default_rng(0)
    table = pd.DataFrame({"v": np.repeat([0.0, 0.1], 30), "F": rng.standard_normal(60) + np.repeat([1, 2], 30)})
    fig, ax = percentile_figure(table, "F", "v", labels={"F": "force (kN)"})
    assert len(ax.lines) >= 3 and ax.get_ylabel() == "force (kN)"
    fig, ax = exceedance_figure(table, "F", "v")
    assert len(ax.lines) == 2 and ax.get_yscale() == "log"
    fig, ax = scatter_figure(table, "v", "F")
    assert len(ax.lines) == 1
    with pytest.raises(st.BadInput, match="G"):
        scatter_figure(table, "v", "G")
    table["kind"] = np.repeat(["a", "b"], 30)
    fig, ax = exceedance_figure(table, "F", "kind")
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["a", "b"]
    for call, name in [(lambda: percentile_figure(table, "F", "kind"), "kind"),
                       (lambda: scatter_figure(table, "kind", "F"), "kind"),
                       (lambda: scatter_figure(table, "v", "F", scale=2.0), "scale"),
                       (lambda: percentile_figure(table, "F", "v", scale="1"), "scale"),
                       (lambda: exceedance_figure({"F": [1.0]}, "F"), "table")]:
        with pytest.raises(st.BadInput, match=name):
            call()


def test_a_function_that_cannot_be_sent_to_the_workers_is_refused_naming_func(user_client):
    import threading
    lock = threading.Lock()
    with pytest.raises(st.BadInput, match="func cannot be sent to the workers"):
        st.run_study(functools.partial(sf.eigen, n=[lock]), [{"x": 1}], client=user_client, progress=False)
