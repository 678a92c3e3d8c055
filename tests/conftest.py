"""Shared fixtures: the paper's two tracks, frequency grids and the paper's N = 5 fits."""

import numpy as np
import pytest

import semitrack as st
from semitrack.base.paper_values import FIT_BANDS

#: The paper's tracks by layout (Table 2 slab, Table 5 ballasted).
PAPER_TRACKS = {"slab": st.slab_track, "ballasted": st.ballasted_track}


@pytest.fixture(params=["slab", "ballasted"])
def track(request):
    """Each of the paper's tracks (Table 2, Table 5)."""
    return PAPER_TRACKS[request.param]()


@pytest.fixture
def paper_grid():
    """The paper's frequency grid: 3 to 2997 Hz in 6 Hz steps (500 frequencies)."""
    return np.arange(3.0, 3000.0, 6.0)


@pytest.fixture(scope="session")
def paper_fits():
    """The paper's fits, computed once per test session: ``{layout: FitResult}``.

    One constrained fit per track as in the paper: N = 5, the paper's band
    (``FIT_BANDS[layout]``), seed 0, default fit frequencies and 20 starts. They go through
    :func:`semitrack.cached_fit`, so any other caller in the session shares them.
    """
    return {layout: st.cached_fit(make(), layout, n_bars=5, band=FIT_BANDS[layout], seed=0)
            for layout, make in PAPER_TRACKS.items()}
