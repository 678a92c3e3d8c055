"""The book's figure functions: each draws from package results and returns (fig, axes).

Small synthetic inputs of the right shape stand in for the studies, so the tests check the
drawing (panels, lines, labels, units), not the numbers.
"""

import matplotlib

matplotlib.use("Agg")  # the tests choose the backend; the library never does

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

from semitrack import plotting  # noqa: E402
from semitrack.base.conventions import ELEMENT_UNITS  # noqa: E402
from semitrack.base.paper_values import FIT_BANDS  # noqa: E402
from semitrack.fe.timedomain import TimeHistory  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_receptance_figure_labels_use_the_package_units():
    f = np.array([10.0, 20.0, 30.0])
    alpha = np.ones((3, 2, 2), dtype=complex)
    fig, axes = plotting.receptance_figure(f, {"exact": alpha, "wavenumber": 2 * alpha})
    assert len(axes) == 3 and len(axes[0].lines) == 2
    assert axes[1].get_ylabel().endswith(f"({ELEMENT_UNITS['alpha12']})")
    assert ELEMENT_UNITS["alpha12"] == "1/N"


def test_long_track_error_figure():
    e = pd.DataFrame({"f (Hz)": [3.0, 9.0], "alpha error": [1e-3, 2e-3], "w1 error": [3e-3, 4e-3]})
    fig, axes = plotting.long_track_error_figure({"slab": e, "ballasted": e})
    assert axes.shape == (2,) and [len(ax.lines) for ax in axes] == [2, 2]
    assert axes[0].get_yscale() == "log"


def test_truncation_figure():
    study = pd.DataFrame({"ends": ["pinned", "pinned", "our system", "our system"], "n_bays": [1, 10, 1, 10],
                          "median error": [0.5, 0.2, 0.02, 0.01], "max error": [2.0, 0.8, 0.05, 0.03]})
    fig, axes = plotting.truncation_figure({"slab": study, "ballasted": study}, FIT_BANDS)
    assert axes.shape == (2, 2)
    assert len(axes[0, 0].lines) == 3  # two kinds of end and the target line
    assert axes[0, 1].get_title() == "ballasted track, 3-750 Hz"


def test_truncated_w1_figure_shades_above_the_band():
    f = np.array([100.0, 800.0, 1200.0])
    table = pd.DataFrame({"infinite track (exact)": [1e-9, 2e-9, 1e-9], "pinned": [1e-9, 3e-9, 1e-9]},
                         index=pd.Index(f, name="f (Hz)"))
    fig, axes = plotting.truncated_w1_figure({"slab": table}, FIT_BANDS, n_bays=10)
    labels = [line.get_label() for line in axes[0].lines]
    assert labels == ["infinite track (exact)", "10 bays, pinned ends"]
    assert len(axes[0].patches) == 1  # the shaded band above 900 Hz


def test_pulse_figure():
    t = np.linspace(0.0, 1e-3, 5)
    hist = TimeHistory(t, np.ones((5, 2)) * 1e-9, ("w(x=0 m)", "w(x=1.95 m)"))
    res = {"reference": hist, "pinned": hist, "equivalent": hist}
    fig, axes = plotting.pulse_figure({"slab": res, "ballasted": res}, n_bays=10, reference_bays=100)
    assert axes.shape == (2, 2)
    assert axes[1, 0].get_ylabel() == "w at x=1.95 m (nm per N)"
    assert [line.get_label() for line in axes[0, 0].lines][0] == "100-bay reference"
