"""Truncated tracks closed by fitted equivalent systems against the infinite track."""

import numpy as np
import pandas as pd
import pytest

import semitrack as st
from semitrack.base.paper_values import FIT_BANDS
from semitrack.fe.truncation import bays_needed, central_w1_by_ends, truncation_study

TRACKS = {"slab": st.slab_track, "ballasted": st.ballasted_track}


@pytest.mark.parametrize("layout", ["slab", "ballasted"])
def test_ten_bays_with_fitted_ends_reproduce_the_infinite_track(layout, paper_fits):
    track, band = TRACKS[layout](), FIT_BANDS[layout]
    system = paper_fits[layout].system  # N = 5 over the paper's band, seed 0
    f = np.arange(band[0], band[1] + 1.0, 6.0)
    study = truncation_study(track, f, n_bays=(10,), ends={"equivalent": ("equivalent", system),
                                                          "pinned": ("pinned", None)})
    eq = study[study.ends == "equivalent"].iloc[0]
    pinned = study[study.ends == "pinned"].iloc[0]
    # Targets: 5 % median and 10 % maximum error of w1 over the fit band at <= 10 bays
    # (measured: slab 1.1 % / 3.5 %, ballasted 0.06 % / 3.7 %).
    assert eq["median error"] < 0.05 and eq["max error"] < 0.10
    # Pinned ends of the same length are far worse (measured max 615 % slab, 73 % ballasted).
    assert pinned["max error"] > 5 * eq["max error"]


def test_exact_ends_leave_only_the_mesh_error():
    """With the exact end stiffness the length does not matter; what is left is the FE mesh's
    error, which falls at second order as the mesh is refined (measured 1.9 % -> 0.46 % max)."""
    track = st.slab_track()
    f = np.arange(3.0, 1500.0, 12.0)
    coarse, fine = (truncation_study(track, f, n_bays=(1, 5), ends={"exact": ("exact", None)}, elements_per_bay=n)
                    for n in (12, 24))
    assert coarse["median error"].max() < 2e-3 and coarse["max error"].max() < 0.025
    assert np.all(coarse["max error"].to_numpy() / fine["max error"].to_numpy() > 3.0)


def test_bays_needed():
    study = pd.DataFrame({"ends": ["a", "a", "a", "b", "b"], "n_bays": [1, 5, 10, 1, 5],
                          "median error": [0.2, 0.04, 0.01, 0.2, 0.1], "max error": [0.5, 0.2, 0.05, 0.9, 0.3]})
    needed = bays_needed(study, median_error=0.05, max_error=0.10)
    assert needed["a"] == 10 and np.isnan(needed["b"])


@pytest.mark.parametrize("layout", ["slab", "ballasted"])
@pytest.mark.parametrize("damping", ["hysteretic", "viscous"])
def test_one_condensed_solve_gives_every_kind_of_end(layout, damping):
    """central_w1_by_ends (the free model condensed to its centre and end DOFs, then closed by each
    kind of end) against each TruncatedTrack's own solve: measured within 5e-13."""
    track = TRACKS[layout](damping=damping)
    system = st.paper_table4() if layout == "slab" else st.paper_table7()
    ends = {"pinned": ("pinned", None), "free": ("free", None), "exact": ("exact", None),
            "equivalent": ("equivalent", system), "boundary": ("boundary", st.fit_boundary(track, n_poles=12))}
    f = np.array([3.0, 117.0, 183.0, 480.0, 1500.0, 2700.0])
    w1 = central_w1_by_ends(track, f, 2, ends, elements_per_bay=8)
    assert list(w1) == list(ends)
    for label, (kind, system) in ends.items():
        direct = st.TruncatedTrack(track, 2, kind, system=system, elements_per_bay=8).central_receptance(f)[:, 0, 0]
        np.testing.assert_allclose(w1[label], direct, rtol=1e-10, atol=0)
    with pytest.raises(TypeError, match="EquivalentSystem"):
        central_w1_by_ends(track, f, 2, {"bad": ("equivalent", None)})
    with pytest.raises(ValueError, match="ends"):
        central_w1_by_ends(track, f, 2, {"bad": ("clamped", None)})
