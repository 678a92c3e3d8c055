"""The book's figure functions: each draws from package results and returns (fig, axes).

Small synthetic inputs of the right shape stand in for the studies, so the tests check the
drawing (panels, lines, labels, units), not the numbers.
"""

import matplotlib

matplotlib.use("Agg")  # the tests choose the backend; the library never does

import pathlib  # noqa: E402
from types import SimpleNamespace  # noqa: E402

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402

import semitrack as st  # noqa: E402
from semitrack import plotting  # noqa: E402
from semitrack.base.conventions import ALL_ELEMENTS, ELEMENT_TEX, ELEMENT_UNITS, ELEMENTS  # noqa: E402
from semitrack.base.paper_values import FIT_BANDS  # noqa: E402
from semitrack.fe.timedomain import TimeHistory  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_figures_belong_to_no_backend_and_leave_the_global_rcparams_alone():
    """A figure function draws on a bare Figure (the CLI selects no backend) in the house style,
    and restores every rcParam it used."""
    before = dict(matplotlib.rcParams)
    with matplotlib.rc_context({"axes.grid": False}):
        fig, axes = plotting.receptance_figure(np.array([10.0, 20.0]), {"exact": np.ones((2, 2, 2))})
        assert not matplotlib.rcParams["axes.grid"]
    assert dict(matplotlib.rcParams) == before
    assert type(fig) is matplotlib.figure.Figure and isinstance(fig.canvas, FigureCanvasAgg)
    assert not plt.get_fignums()  # not one pyplot figure
    assert all(ax.xaxis._major_tick_kw.get("gridOn", False) for ax in axes)  # the house style's grid


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


# ------------------------------------------------------------------------------------------------
# Every figure, drawn from small synthetic inputs, for the checks that apply to all of them
# ------------------------------------------------------------------------------------------------
F = np.geomspace(3.0, 3000.0, 40)
ALPHA = np.empty((F.size, 2, 2), dtype=complex)
ALPHA[:, 0, 0] = 1e-9 * np.exp(1j * F / 1e3) * (1 + F / 1e3)
ALPHA[:, 0, 1] = ALPHA[:, 1, 0] = 2e-9 * np.exp(0.5j) * (1 + F / 1e3)
ALPHA[:, 1, 1] = 1e-8 * np.exp(-1j * F / 2e3) / (1 + F / 1e3)


def _study(levels=(1.0, 0.3, 0.1, 0.03, 0.01, 0.003, 0.001, 1e-4)):
    """A truncation study whose curves cover the whole height of the panels (nowhere left for a legend)."""
    bays = np.array([1, 2, 5, 10, 20, 40, 80, 160])
    ends = ["pinned", "free", "paper system", "our system", "exact end stiffness", "a", "b", "c"]
    rows = [dict(ends=end, n_bays=n, **{"median error": lv * n ** -0.2, "max error": 3 * lv * n ** -0.2})
            for end, lv in zip(ends, levels) for n in bays]
    return pd.DataFrame(rows)


def _central(scale=1.0):
    return SimpleNamespace(w1=scale * ALPHA[:, 0, 0], psi2=ALPHA[:, 1, 1], Q2=1.0 + F / 1e3, M1=0.1 + F / 1e4,
                           det=1e15 * (1 + F / 100))


def _time_history():
    t = np.linspace(0.0, 3e-2, 50)
    u = np.column_stack([np.sin(300 * t), np.cos(300 * t)]) * 1e-9
    return TimeHistory(t, u, ("w(x=0 m)", "w(x=1.95 m)"))


def _all_figures():
    """(name, fig) of every figure function of the module."""
    curves = pd.DataFrame({"infinite track (exact)": np.abs(ALPHA[:, 0, 0]), "pinned": 2 * np.abs(ALPHA[:, 0, 0])},
                          index=pd.Index(F, name="f (Hz)"))
    errors = pd.DataFrame({"N = 5 system": F / 3e3, "broadband boundary": 3e3 / F / 1e3}, index=F)
    conv = pd.DataFrame([{"f (Hz)": f, "beta factor": b, "dx (m)": dx, "error": dx / b}
                         for f in (3.0, 183.0) for b in (1, 2) for dx in (0.01, 0.04)])
    orders = pd.DataFrame({"n_poles": [12, 24], "median error (%)": [2.0, 1.0], "max error (%)": [6.0, 5.0]})
    hist = _time_history()
    x = np.linspace(-1.5, 1.5, 11)
    yield "receptance", plotting.receptance_figure(F, {"exact": ALPHA, "wavenumber": 1.1 * ALPHA})[0]
    yield "phase", plotting.phase_figure(F, {"exact": ALPHA, "wavenumber": 1.1 * ALPHA})[0]
    yield "fields", plotting.fields_figure(x, ALPHA[:11], "fields")[0]
    yield "convergence", plotting.convergence_figure(conv)[0]
    yield "central", plotting.central_response_figure(F, {"exact": _central(), "wavenumber": _central(1.1)})[0]
    yield "schematic", plotting.equivalent_schematic(st.paper_table7()).figure
    yield "long track", plotting.long_track_error_figure({"slab": errors.reset_index().rename(
        columns={"index": "f (Hz)", "N = 5 system": "alpha error", "broadband boundary": "w1 error"})})[0]
    yield "truncation", plotting.truncation_figure({"slab": _study(), "ballasted": _study()}, FIT_BANDS)[0]
    yield "truncated w1", plotting.truncated_w1_figure({"slab": curves, "ballasted": curves}, FIT_BANDS, 10)[0]
    res = {"reference": hist, "pinned": hist, "equivalent": hist, "boundary": hist}
    yield "pulse", plotting.pulse_figure({"slab": res, "ballasted": res}, 10, 100)[0]
    yield "band error", plotting.band_error_figure({"slab": errors, "ballasted": errors}, FIT_BANDS)[0]
    yield "boundary receptance", plotting.boundary_receptance_figure(
        F, {"slab": {"broadband boundary": ALPHA}, "ballasted": {"broadband boundary": ALPHA}})[0]
    yield "order", plotting.order_error_figure({"slab, hysteretic": orders, "slab, viscous": orders})[0]
    yield "passivity", plotting.passivity_margin_figure(F, {"slab": F / 1e3}, (3.0, 3000.0))[0]
    yield "boundary w1", plotting.boundary_w1_figure({"slab": curves}, FIT_BANDS, 10)[0]
    yield "boundary pulse", plotting.boundary_pulse_figure({"slab": res}, 10, 100)[0]
    linear = SimpleNamespace(f=F, curves={(n, w): np.abs(ALPHA[:, 0, 0]) for n in ("slab", "ballasted")
                                          for w in plotting.POSITION_STYLE})
    yield "linear force", plotting.linear_force_figure(linear)[0]
    bands = np.array([50.0, 63.0, 80.0])
    transfer = SimpleNamespace(centres=bands, level=np.array([160.0, 162.0, 165.0]), linear_level=np.full(3, 161.0))
    transfers = {(n, m): transfer for n in ("slab", "ballasted") for m in ("boundary", "pinned")}
    yield "band levels", plotting.band_level_figure(transfers, {"pinned": dict(marker="x", ls="")}, "boundary")[0]
    t = np.linspace(0.0, 0.05, 200)
    run = SimpleNamespace(t=t, force=1e5 * (1 + 0.1 * np.sin(2e3 * t)), x=np.linspace(-1.5, 1.5, 200), speed=60.0,
                          force_spectrum=lambda after: (np.linspace(0.0, 2000.0, 50), np.linspace(1.0, 10.0, 50)))
    yield "force history", plotting.force_history_figure({"a": run, "b": run}, (0.0, 0.05), zero_line=True)[0]
    yield "rolling", plotting.rolling_figure({"300 km/h": run}, 0.65, after=0.0)[0]
    bands3 = np.array([250.0, 500.0, 1000.0])
    tdr = SimpleNamespace(centres=bands3, decay_rate=np.array([3.0, 1.0, 0.5]), valid=np.array([True, False, True]),
                          wave_attenuation=np.array([2.5, 0.8, 0.4]))
    yield "decay", plotting.decay_rate_figure({"slab": tdr}, st.ISO3095_TDR_LIMIT)[0]
    changes = {f"case {i}": np.abs(ALPHA[:, :2, 0]) * (1 + 0.1 * i) for i in range(7)}  # more cases than colours
    yield "local change", plotting.local_change_figure(F, changes, ("above", "a bay on"), "case 0")[0]


@pytest.fixture(scope="module")
def figures():
    """Every figure, drawn (so that layouts, tick labels and extents are final)."""
    drawn = []
    for name, fig in _all_figures():
        plt.close(fig)  # out of pyplot's hands, so that closing all figures after each test spares these
        FigureCanvasAgg(fig).draw()
        drawn.append((name, fig))
    return drawn


def _visible_tick_labels(ax):
    return [t.get_text() for t in ax.get_xticklabels() if t.get_visible() and t.get_text()]


def _lowest_shown(fig):
    """Panels (with an x-axis) that no other panel of the same column lies directly below."""
    axes = [ax for ax in fig.axes if ax.get_visible() and ax.axison]
    for ax in axes:
        box = ax.get_position()
        below = [o for o in axes if o is not ax and o.get_position().y1 < box.y0
                 and abs(o.get_position().x0 - box.x0) < 0.02]
        if not below:
            yield ax


def test_every_panel_without_a_panel_below_has_frequency_tick_labels(figures):
    for name, fig in figures:
        for ax in _lowest_shown(fig):
            assert _visible_tick_labels(ax), f"{name}: panel '{ax.get_ylabel()}' has no x tick labels"


def test_central_response_q2_panel_has_tick_labels():
    fig, axes = plotting.central_response_figure(F, {"exact": _central()})
    fig.canvas.draw()
    assert axes[0, 2].get_ylabel().startswith(r"$|\tilde Q_2|$")
    assert _visible_tick_labels(axes[0, 2]) and axes[0, 2].get_xlabel() == "Frequency (Hz)"
    assert not _visible_tick_labels(axes[0, 0])  # shown by the panel below it
    assert not axes[1, 2].axison and axes[1, 2].get_legend() is not None  # the spare panel holds the legend


def _display_points(line):
    """The line's vertices in display coordinates, with 20 points on each segment in between."""
    xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
    xy = xy[np.isfinite(xy).all(axis=1)]
    steps = np.linspace(0.0, 1.0, 20)[:, None, None]
    return (xy[:-1] + steps * (xy[1:] - xy[:-1])).reshape(-1, 2)


def test_no_legend_covers_a_curve(figures):
    for name, fig in figures:
        renderer = fig.canvas.get_renderer()
        legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
        for legend in legends:
            box = legend.get_window_extent(renderer)
            for ax in fig.axes:
                for line in ax.lines:
                    x, y = _display_points(line).T
                    covered = (box.x0 <= x) & (x <= box.x1) & (box.y0 <= y) & (y <= box.y1)
                    assert not covered.any(), f"{name}: the legend covers '{line.get_label()}'"


def test_truncation_legend_is_below_the_panels():
    fig, axes = plotting.truncation_figure({"slab": _study()}, FIT_BANDS)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    (legend,) = fig.legends
    box = legend.get_window_extent(renderer)
    assert all(box.y1 <= ax.get_window_extent(renderer).y0 for ax in axes.flat)
    assert "targets: 5 % median, 10 % max" in [t.get_text() for t in legend.get_texts()]


def _axis_texts(fig):
    for ax in fig.axes:
        yield from (ax.get_xlabel(), ax.get_ylabel(), ax.get_title())


def test_no_label_writes_another_unit_for_alpha12(figures):
    for name, fig in figures:
        for text in _axis_texts(fig):
            assert "rad/N" not in text and "m/(N m)" not in text, f"{name}: {text!r}"
    source = "".join(p.read_text() for p in pathlib.Path(plotting.__file__).parent.glob("*.py"))
    assert "rad/N" not in source and "m/(N m)" not in source


def test_receptance_labels_take_their_units_from_the_conventions(figures):
    by_name = dict(figures)
    fields = by_name["fields"].axes
    assert all(ax.get_ylabel().endswith(f" ({ELEMENT_UNITS[e]})") for ax, e in zip(fields, ALL_ELEMENTS))
    central = by_name["central"].axes
    assert central[0].get_ylabel().endswith(f"({ELEMENT_UNITS['alpha11']})")
    assert central[1].get_ylabel().endswith(f"({ELEMENT_UNITS['alpha22']})")


def test_phase_panels_use_the_symbols_of_the_magnitude_panels():
    _, mag = plotting.receptance_figure(F, {"exact": ALPHA})
    _, phase = plotting.phase_figure(F, {"exact": ALPHA})
    for m_ax, p_ax, element in zip(mag, phase, ELEMENTS):
        symbol = ELEMENT_TEX[element].strip("$")
        assert p_ax.get_title() == m_ax.get_title() == ELEMENT_TEX[element]
        assert symbol in p_ax.get_ylabel() and symbol in m_ax.get_ylabel()
        assert p_ax.get_ylabel().endswith("(rad)")


# ------------------------------------------------------------------------------------------------
# The equivalent-system schematic
# ------------------------------------------------------------------------------------------------
#: Our ballasted N = 5 fit (3 digits): bars 4 and 5 only 5 and 3 cm long, which crowds their labels.
FITTED_BALLASTED = dict(
    m=[1.31, 31.9, 21.1, 710.0, 1.75e4], J=[0.00916, 1.2, 1.15, 0.414, 4.18], L=[0.167, 0.388, 0.466, 0.0483, 0.0309],
    k=[5.28e6, 1.28e8, 8.49e7, 2.85e9, 7.05e10], c_l=[3.47e6, 0.00163, 9.29e4, 1.86e8, 6.48e6],
    c_r=[0.00185, 6.94e3, 5.67e6, 0.00269, 2.08e6], k_phi=[1.59e7, 1.49e7, 3.95e7, 6.2],
    c_phi=[589.0, 0.00132, 277.0, 1.62e5], mu=[3.06, 74.3, 49.2, 1.65e3, 4.09e4],
    s=[1.96e6, 4.75e7, 3.15e7, 1.06e9, 2.62e10], d_l=[0.00366, 1.63e4, 1.48, 1.07, 2.7e7],
    d_r=[2.45e5, 3.8e4, 3.2, 8.56, 2.08e8])
#: Our slab N = 5 fit (3 digits): bar 4 is degenerate (m = 3.9e-7 kg).
FITTED_SLAB = dict(
    m=[1.19, 21.8, 36.8, 3.92e-7, 222.0], J=[0.00151, 0.658, 1.09, 1.2e-8, 5.74],
    L=[0.0712, 0.348, 0.344, 0.349, 0.321],
    k=[7.92e5, 1.45e7, 2.45e7, 0.261, 1.48e8], c_l=[4.71e-5, 4.71e-5, 1.51e3, 1.94e3, 4.71e-5],
    c_r=[4.71e-5, 1.24e3, 9.78e3, 4.71e-5, 7.64e4], k_phi=[2.27e7, 1.8e7, 7.25e6, 2.58e6],
    c_phi=[204.0, 1.01e3, 1.4e3, 3.99e3])
SCHEMATIC_SYSTEMS = {"Table 4": st.paper_table4, "Table 7": st.paper_table7,
                     "fitted slab": lambda: st.SlabEquivalent(**FITTED_SLAB),
                     "fitted ballasted": lambda: st.BallastedEquivalent(**FITTED_BALLASTED)}


def _text_box(text, renderer):
    """The extent of a label's own text (an annotation's extent would include its leader line)."""
    return matplotlib.text.Text.get_window_extent(text, renderer)


def _drawn_schematic(system):
    ax = plotting.equivalent_schematic(system)
    ax.figure.canvas.draw()
    return ax, ax.figure.canvas.get_renderer()


@pytest.mark.parametrize("name", SCHEMATIC_SYSTEMS)
def test_schematic_labels_do_not_overlap_and_stay_inside(name):
    ax, renderer = _drawn_schematic(SCHEMATIC_SYSTEMS[name]())
    boxes = [_text_box(t, renderer) for t in ax.texts]
    assert len(boxes) >= 2 * 5  # every bar and every support labelled
    frame = ax.get_window_extent(renderer)
    for i, a in enumerate(boxes):
        assert frame.x0 <= a.x0 and a.x1 <= frame.x1 and frame.y0 <= a.y0 and a.y1 <= frame.y1, ax.texts[i].get_text()
        for j in range(i):
            assert not a.overlaps(boxes[j]), (ax.texts[i].get_text(), ax.texts[j].get_text())


def test_ballasted_fit_bar_labels_were_crowded_and_are_now_apart():
    ax, renderer = _drawn_schematic(SCHEMATIC_SYSTEMS["fitted ballasted"]())
    bars = {t.get_text().split("\n")[0]: _text_box(t, renderer)
            for t in ax.texts if t.get_text().startswith("bar")}
    assert not bars["bar 4"].overlaps(bars["bar 5"])
    # without moving them, labels centred on these 3-5 cm bars would overlap
    centres = ax.transData.transform([[1.02 + 0.0483 / 2, 0], [1.0693 + 0.0309 / 2, 0]])[:, 0]
    assert centres[1] - centres[0] < bars["bar 4"].width


def _gids(ax, gid):
    return [a for a in [*ax.lines, *ax.patches] if a.get_gid() == gid]


def test_schematic_draws_a_dashpot_for_each_positive_damping():
    p4 = st.paper_table4().parameters()
    ax = plotting.equivalent_schematic(st.paper_table4())
    assert len(_gids(ax, "damper")) == np.count_nonzero(p4["c_l"]) + np.count_nonzero(p4["c_r"]) == 5
    assert len(_gids(ax, "spring")) == 2 * np.count_nonzero(p4["k"])
    undamped = st.SlabEquivalent(m=10.0, J=0.2, L=0.6, k=1e7, c_l=0.0, c_r=0.0, k_phi=[], c_phi=[])
    assert _gids(plotting.equivalent_schematic(undamped), "damper") == []
    p7 = st.paper_table7().parameters()
    n7 = sum(np.count_nonzero(p7[c]) for c in ("c_l", "c_r", "d_l", "d_r"))
    assert len(_gids(plotting.equivalent_schematic(st.paper_table7()), "damper")) == n7


def test_schematic_labels_carry_units():
    ax = plotting.equivalent_schematic(st.paper_table7())
    text = "\n".join(t.get_text() for t in ax.texts)
    for unit in ("N/m", "N s/m", "N m/rad", "N m s/rad", "kg"):
        assert f" {unit}" in text
    assert all(" N/m" in line for line in text.splitlines() if line.startswith(("$k$", "$s$")))
    assert "N/m" not in ax.get_title()


@pytest.mark.parametrize("name, massless", [("Table 4", {2, 4}), ("fitted slab", {4}), ("Table 7", set())])
def test_schematic_draws_massless_bars_dashed_and_says_so(name, massless):
    system = SCHEMATIC_SYSTEMS[name]()
    ax = plotting.equivalent_schematic(system)
    for j in range(1, system.n_bars + 1):
        (bar,) = _gids(ax, f"bar {j}")
        dashed = bar.get_linestyle() in ("--", "dashed")
        assert dashed == (j in massless), j
        (label,) = [t.get_text() for t in ax.texts if t.get_text().startswith(f"bar {j}")]
        assert ("massless" in label) == (j in massless)


def test_spread_keeps_labels_apart_near_their_anchors_and_inside():
    centres = plotting.schematic._spread([10.0, 11.0, 12.0, 50.0, 99.0], [6.0, 6.0, 6.0, 6.0, 6.0], 0.0, 100.0)
    assert np.all(np.diff(centres) >= 6.0 - 1e-9)
    assert np.isclose(centres[:3].mean(), 11.0)  # the crowded three are centred on their anchors
    assert centres[3] == 50.0 and centres[4] == 97.0  # the last one is pushed inside the row


def test_long_titles_are_broken_to_fit_the_figure():
    """A title at the house font sizes (large enough to read at the book's width) that would run
    past the figure's edge is broken into lines inside it; a short one is left as it is."""
    f = np.array([10.0, 20.0])
    long_title = "Slab track against the paper's equivalent system and ours, " * 3 + "(as the paper's Fig. 8)"
    fig, _ = plotting.receptance_figure(f, {"exact": np.ones((2, 2, 2))}, long_title)
    title = fig._suptitle
    assert "\n" in title.get_text() and title.get_text().replace("\n", " ") == long_title
    assert title.get_window_extent(fig.canvas.get_renderer()).width <= fig.get_figwidth() * fig.dpi
    fig, _ = plotting.receptance_figure(f, {"exact": np.ones((2, 2, 2))}, "Slab track")
    assert fig._suptitle.get_text() == "Slab track"


def test_figure_text_is_at_least_10_px_at_the_page_s_width():
    """A wide multi-panel figure (3 panels, 15.4 in) shown at the book's 690-px column: every text
    artist, tick labels included, at least 10 px high once drawn; a narrow figure keeps its sizes."""
    import matplotlib as mpl

    from semitrack.plotting.style import MIN_TEXT_PX, PAGE_WIDTH_PX, house_figure, panels

    @house_figure
    def wide():
        fig, axes = panels(3, figsize=(15.4, 3.6))
        for ax in axes:
            ax.plot([0, 1], [0, 1], label="a line")
            ax.set_title("a title")
            ax.set_xlabel("x (m)")
        axes[0].legend()
        return fig, axes

    fig, _ = wide()
    fig.canvas.draw()
    scale = PAGE_WIDTH_PX / (fig.get_figwidth() * 72.0)  # px per pt at page width
    sizes = [t.get_fontsize() for t in fig.findobj(mpl.text.Text) if t.get_text()]
    assert sizes and min(sizes) * scale >= MIN_TEXT_PX - 1e-9
    narrow, _ = plotting.force_history_figure({}, (0.0, 1.0))  # 9 in: 12 pt is 11.5 px, left as it is
    narrow.canvas.draw()
    assert {t.get_fontsize() for t in narrow.axes[0].get_xticklabels()} == {12.0}

    @house_figure
    def small():  # 4 in at 110 dpi: 440 px, shown at its own size, not scaled up to the column
        fig, (ax,) = panels(1, figsize=(4.0, 3.0))
        ax.plot([0, 1], [0, 1], label="a line")
        ax.legend(fontsize=5.0)
        ax.tick_params(labelsize=5.0)
        return fig, ax

    fig, _ = small()
    fig.canvas.draw()
    assert fig.dpi * fig.get_figwidth() < PAGE_WIDTH_PX
    sizes = [t.get_fontsize() for t in fig.findobj(mpl.text.Text) if t.get_text()]
    assert sizes and min(sizes) * fig.dpi / 72.0 >= MIN_TEXT_PX - 1e-9  # px at its own size


def test_the_shipped_fonts_are_found_whatever_the_font_cache_holds(monkeypatch):
    """A font cache another install wrote (no STIX in its list, as on a machine whose venv was removed):
    the figures' module registers matplotlib's own fonts, and STIX resolves to its file."""
    import copy
    from pathlib import Path

    import matplotlib as mpl
    from matplotlib import font_manager

    from semitrack.plotting import style

    stale = copy.copy(font_manager.fontManager)
    stale.ttflist = [f for f in font_manager.fontManager.ttflist if "STIX" not in Path(f.fname).name]
    monkeypatch.setattr(font_manager, "fontManager", stale)
    assert not any("STIX" in f.name for f in stale.ttflist)
    style._register_shipped_fonts()
    assert any(Path(f.fname).name == "STIXGeneral.ttf" for f in font_manager.fontManager.ttflist)
    found = Path(font_manager.findfont("STIXGeneral", fallback_to_default=False))
    assert found.name == "STIXGeneral.ttf" and found.is_file()
    assert found.parent == Path(mpl.get_data_path()) / "fonts" / "ttf"
