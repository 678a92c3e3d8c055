"""Shared fixtures: the paper's two tracks and frequency grids."""

import numpy as np
import pytest

import semitrack as st


@pytest.fixture(params=["slab", "ballasted"])
def track(request):
    """Each of the paper's tracks (Table 2, Table 5)."""
    return st.slab_track() if request.param == "slab" else st.ballasted_track()


@pytest.fixture
def paper_grid():
    """The paper's frequency grid: 3 to 2997 Hz in 6 Hz steps (500 frequencies)."""
    return np.arange(3.0, 3000.0, 6.0)
