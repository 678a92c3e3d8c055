"""Shared fixtures: the paper's two tracks, frequency grids and the paper's N = 5 fits."""

import contextlib
import os
from collections.abc import Mapping

import numpy as np
import pytest
from threadpoolctl import threadpool_limits

import semitrack as st
from semitrack.base.paper_values import FIT_BANDS

try:  # POSIX: the test workers of one run take turns at the shared fit cache
    import fcntl
except ImportError:  # pragma: no cover - elsewhere each worker computes the fits it needs itself
    fcntl = None

#: The paper's tracks by layout (Table 2 slab, Table 5 ballasted).
PAPER_TRACKS = {"slab": st.slab_track, "ballasted": st.ballasted_track}

# The suite runs on parallel workers (pytest-xdist, ``-n auto --dist loadgroup`` in pyproject.toml).
# Tests are handed out one by one, in collection order, to whichever worker runs low, except the
# modules below, whose module-scoped fixtures are expensive (boundary fits, the unconstrained fit,
# every figure drawn): each goes whole to one worker. The longest tests start first, so that the
# workers finish together: the README test (~25 s), then those modules.
_WHOLE_MODULES = ("test_boundary.py", "test_fitting.py", "test_plotting.py")
_FIRST = ("test_readme.py", *_WHOLE_MODULES)


_BLAS_LIMIT = []


def pytest_configure(config):
    """In a parallel worker, BLAS on one thread: every core already runs a worker, and threaded
    BLAS calls outside the package's own one-thread sections (the test code's, the exact
    method's) only contend (measured: the suite 90 s with OPENBLAS_NUM_THREADS=1, 104 s without)."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        _BLAS_LIMIT.append(threadpool_limits(limits=1, user_api="blas"))


def pytest_collection_modifyitems(items):
    """Long tests first; a stable sort keeps every module's own order."""
    rank = {name: i for i, name in enumerate(_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(_FIRST)))


@pytest.hookimpl(optionalhook=True)  # a hook of pytest-xdist: ignored when it is not installed
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadgroup``: one test at a time, but :data:`_WHOLE_MODULES` whole, in collection order.

    xdist's own loadgroup reads ``xdist_group`` marks through the test ids, which it rewrites in a
    way pytest 9 ignores (every test went alone); the grouping here needs neither.
    """
    if config.getvalue("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadScopeScheduling

    class WholeModules(LoadScopeScheduling):
        def _split_scope(self, nodeid):
            module = nodeid.split("::", 1)[0]
            return module if module.rsplit("/", 1)[-1] in _WHOLE_MODULES else nodeid

    return WholeModules(config, log)


@pytest.fixture(params=["slab", "ballasted"])
def track(request):
    """Each of the paper's tracks (Table 2, Table 5)."""
    return PAPER_TRACKS[request.param]()


@pytest.fixture
def paper_grid():
    """The paper's frequency grid: 3 to 2997 Hz in 6 Hz steps (500 frequencies)."""
    return np.arange(3.0, 3000.0, 6.0)


@pytest.fixture(scope="session")
def fit_cache_dir(tmp_path_factory):
    """A cache folder of :func:`semitrack.cached_fit` for this test run, shared by its workers.

    The suite runs in parallel processes (pytest-xdist, ``-n`` in pyproject.toml); each has its
    own base temporary folder below one folder of the run, where the cache lives, so a fit one
    worker computed is read back by the others. Without xdist it is a folder of the session.
    """
    base = tmp_path_factory.getbasetemp()
    folder = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "fit-cache"
    folder.mkdir(exist_ok=True)
    return folder


@contextlib.contextmanager
def _exclusive(path):
    """Hold the lock file ``path`` (one worker computes a shared fit while the others wait)."""
    if fcntl is None:
        yield
        return
    with open(path, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


class _PaperFits(Mapping):
    """``{layout: FitResult}``, each fit computed (or read from the run's cache) when first asked for."""

    def __init__(self, folder):
        self._folder, self._fits = folder, {}

    def __getitem__(self, layout):
        if layout not in self._fits:
            make = PAPER_TRACKS[layout]
            with _exclusive(self._folder / f".lock-{layout}"):
                self._fits[layout] = st.cached_fit(make(), layout, n_bars=5, band=FIT_BANDS[layout], seed=0,
                                                   cache_dir=self._folder)
        return self._fits[layout]

    def __iter__(self):
        return iter(PAPER_TRACKS)

    def __len__(self):
        return len(PAPER_TRACKS)


@pytest.fixture(scope="session")
def paper_fits(fit_cache_dir):
    """The paper's fits, computed once per test run: ``{layout: FitResult}``.

    One constrained fit per track as in the paper: N = 5, the paper's band
    (``FIT_BANDS[layout]``), seed 0, default fit frequencies and 20 starts. Each is computed
    when a test first asks for it, through :func:`semitrack.cached_fit` with the run's shared
    cache folder: any other caller in the process shares it, and a parallel worker reads what
    another one computed (waiting while it is being computed).
    """
    return _PaperFits(fit_cache_dir)


# --- Hypothesis settings profiles (tests/test_property_*.py) ---------------------------------------------
# "ci", the default: bounded (about two minutes of the suite on two cores), the same examples at every
# run (derandomize), no shrinking and no example database; "long" on demand, with
# `pytest --hypothesis-profile=long`: many more random examples, shrunk to the smallest.
from hypothesis import HealthCheck, Phase, settings  # noqa: E402

_HEALTH = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much,
           HealthCheck.function_scoped_fixture, HealthCheck.differing_executors]
settings.register_profile("ci", max_examples=25, deadline=None, derandomize=True, database=None,
                          phases=(Phase.explicit, Phase.generate), suppress_health_check=_HEALTH,
                          print_blob=False)
settings.register_profile("long", max_examples=1000, deadline=None, database=None, suppress_health_check=_HEALTH,
                          print_blob=True)
settings.load_profile("ci")


@pytest.fixture
def clean_environment(monkeypatch):
    """No CI and no SEMITRACK_PROGRESS, whatever the machine running the tests sets (tests of progress bars)."""
    monkeypatch.delenv("CI", raising=False)
    monkeypatch.delenv("SEMITRACK_PROGRESS", raising=False)
    return monkeypatch
