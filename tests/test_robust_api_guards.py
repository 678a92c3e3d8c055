"""The public API's guards, one class of issue 34 at a time: work refused before it is allocated, nothing
outside a model's reach silently ignored, strings never taken as numbers, refusals in one line naming
the parameter.

Each case failed on the code before these guards (a raw ``MemoryError``, a run still going at 30 s, a
change accepted and ignored, a numpy error, a message over several lines); each refusal here must
come within 1 s (:func:`refusals.refused`). The property-based suite (``tests/test_property_api.py``)
draws such arguments for every public callable; these are the cases the issue names, kept as
plain tests so that a regression names its class.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from refusals import refused

import semitrack as st
import semitrack.interaction.moving_green  # noqa: F401 - imported here: a refusal's second is not the imports'
from semitrack.base.errors import BadInput, InputError, InputTypeError, UnreadableFile

SLAB, BALLASTED = st.slab_track(), st.ballasted_track()
ONE_SECOND = 1.0  # of CPU: the work before the refusal, whatever else the machine runs


# --- work guarded before any allocation -------------------------------------------------------------
@pytest.mark.parametrize(("options", "words"), [
    ({"df": 1e-6}, ("df=1e-06", "lines")),  # was a raw MemoryError after 2.4 s (1.1 GB asked)
    ({"df": 1e-4}, ("df=0.0001", "lines")),  # was refused only after 9 s
    ({"band": (100, 1e6)}, ("band", "20000 Hz")),  # ran for more than 20 s
])
def test_the_decay_rate_refuses_its_work_before_allocating_it(options, words):
    refused(lambda: st.track_decay_rate(SLAB, **options), InputError, *words, cpu=ONE_SECOND)


@pytest.mark.parametrize("case", ["far change", "far response point", "a million points"])
def test_the_exact_track_refuses_a_solve_it_cannot_finish(case):
    calls = {"far change": lambda: st.InfiniteTrack(SLAB, {10**6: {"kv": 1e8}}).receptance([100.0], 0.0, [0.0]),
             "far response point": lambda: st.InfiniteTrack(SLAB, {0: {"kv": 1e8}}).receptance([100.0], 0.0, [5e5]),
             "a million points": lambda: st.InfiniteTrack(SLAB).receptance([100.0, 200.0], 0.0, np.zeros(10**6))}
    refused(calls[case], InputError, "more than the limit", cpu=ONE_SECOND)


def test_a_near_change_still_solves():
    h = st.InfiniteTrack(SLAB, {3: {"kv": 1e8}}).receptance([100.0], 0.0, [0.0, 2.0])
    assert h.shape == (1, 2, 2, 2) and np.all(np.isfinite(h))


def test_a_perfect_track_s_core_encloses_the_points_alone_wherever_they_are():
    """A perfect track's receptance 2 km from the origin is its receptance at the origin (one period
    shifted 3334 times) and costs as little: the core once ran from support 0 to the points (3.5 s for a
    run at x = 3 km, found by the property suite), and 650 km away it was refused."""
    f, d = np.geomspace(10.0, 3000.0, 20), SLAB.spacing
    near = st.InfiniteTrack(SLAB).receptance(f, 0.13, [0.13, 0.5])
    for shift in (3334 * d, 10**6 * d):
        far = st.InfiniteTrack(SLAB).receptance(f, 0.13 + shift, [0.13 + shift, 0.5 + shift])
        assert np.abs(far - near).max() < 1e-9 * np.abs(near).max()
    xs, _, x_left, x_right = st.InfiniteTrack(SLAB)._nodes(np.array([0.13 + 3334 * d]))
    assert x_right - x_left < 3.5 * d and xs.size < 10  # a bay either side of the point's bay


@pytest.mark.parametrize(("call", "words"), [
    (lambda: st.moving_green_kernels(BALLASTED, 1e-308, dt=1e-4), ("speed must be from",)),
    (lambda: st.roughness_from_spectrum(20.0).sampled(1e-4, 10**10), ("n=10000000000",)),
    (lambda: st.default_fit_frequencies((3.0, 300.0), n=10**9), ("n=1000000000",)),
    (lambda: st.error_band_grid((3.0, 300.0), 1e-100), ("df=1e-100",)),
])
def test_hostile_sizes_are_refused_before_the_allocation(call, words):
    refused(call, InputError, *words, cpu=ONE_SECOND)


# --- nothing outside a model's reach silently ignored -------------------------------------------------
def test_a_change_beyond_a_truncated_model_is_refused():
    refused(lambda: st.TruncatedTrack(SLAB, 4, changes={100: {"kv": 1e8}}), InputError, "changes", "support 100",
            "outside the model")
    model = st.TruncatedTrack(SLAB, 4)
    refused(lambda: model.with_changes({-5: {"kv": 1e8}}), InputError, "support -5", "outside the model")
    assert model.with_changes({3: {"kv": 1e8}}).changes  # the model's own last support is one of its own


def test_a_profile_no_wheel_reaches_is_warned():
    model = st.TruncatedTrack(BALLASTED, 4, elements_per_bay=4)
    with pytest.warns(RuntimeWarning, match="no wheel meets it"):
        st.wheel_rail_response(model, st.Wheel(), speed=20.0, dt=1e-4, duration=0.02, ramp=0.005,
                               profile=st.DippedWeld(0.01, x=500.0))


# --- strings, NaN and wrong shapes: refused naming the parameter ----------------------------------------
@pytest.mark.parametrize(("offsets", "cls"), [([np.nan], InputError), (["0.3"], InputTypeError),
                                              ([[0.0, 2.5], [0.0, 2.5]], InputError), ([], InputError)])
def test_offsets_that_are_not_positions(offsets, cls):
    refused(lambda: st.moving_green_kernels(BALLASTED, 20.0, dt=1e-4, offsets=offsets), cls, "offsets",
            cpu=ONE_SECOND)


@pytest.mark.parametrize(("x", "cls"), [([], InputError), ("0.3", InputTypeError), ([1.0, [2.0]], InputTypeError),
                                        (1e308, InputError)])
def test_a_contact_position_that_is_not_one(x, cls):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)
        refused(lambda: st.wheel_rail_force(SLAB, [100.0], st.Wheel(), x=x), cls, "x")


def test_the_old_name_of_x_takes_no_string_either():
    model = st.TruncatedTrack(BALLASTED, 4, elements_per_bay=4)
    with pytest.warns(DeprecationWarning):
        with pytest.raises(InputTypeError, match="x"):
            st.wheel_rail_response(model, st.Wheel(), speed=20.0, dt=1e-4, duration=0.02, x_contact="0")


@pytest.mark.parametrize("x", [np.nan, np.inf, 1e308])
def test_a_weld_is_somewhere(x):
    refused(lambda: st.DippedWeld(0.01, x=x), InputError, "x")


@pytest.mark.parametrize("levels", [[1e308], [200.0]])
def test_roughness_levels_beyond_any_rail_name_the_levels(levels):
    refused(lambda: st.roughness_from_spectrum(20.0, wavelengths=[0.05], levels=levels), InputError, "levels")


def test_an_array_in_a_message_stays_on_one_line():
    message = refused(lambda: st.slab_track(E=np.ones((2, 2))), InputTypeError, "E")
    assert "array([[1., 1.], [1., 1.]])" in message
    assert str(InputError("path a\nb.toml")) == "path a\\nb.toml"  # a line break in the user's text: written \n


def test_a_choice_is_never_an_array():
    refused(lambda: st.example_track(np.array(["slab", "slab"])), BadInput, "name")
    refused(lambda: st.TruncatedTrack(SLAB, 2, ends=np.ones((2, 2))), BadInput, "ends")


def test_a_record_built_by_hand_is_refused_naming_the_field():
    refused(lambda: st.ErrorSummary(median="", max=1.0, per_element={}), InputTypeError, "ErrorSummary.median")
    refused(lambda: st.CentralResponse(f=("50", "200"), w1=np.ones(2), psi2=np.ones(2), Q2=np.ones(2),
                                       M1=np.ones(2), method="transfer"), InputTypeError, "CentralResponse.f")
    summary = st.ErrorSummary(median=0.1, max=0.2, per_element={"alpha11": [0.1, 0.2]})
    assert summary.element_maxima() == {"alpha11": 0.2}


# --- paths ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("loader", [st.load_boundary, st.load_matrix_system, st.load_system_json,
                                    st.load_track_toml, st.load_frequency_table])
def test_a_path_of_the_wrong_type_or_empty_is_refused_naming_path(loader):
    refused(lambda: loader(1.5), InputTypeError, "path")
    refused(lambda: loader(""), BadInput, "path")


def test_a_missing_file_is_both_an_oserror_and_a_refusal(tmp_path):
    with pytest.raises(UnreadableFile) as info:
        st.load_system_json(tmp_path / "missing.json")
    assert isinstance(info.value, FileNotFoundError) and isinstance(info.value, BadInput)  # callers' except holds
    assert info.value.filename == str(tmp_path / "missing.json")
    with pytest.raises(IsADirectoryError):
        st.load_system_json(tmp_path)


# --- the long Hypothesis profile's classes (stop 43): each failed before, a raw error or a wrong name --------
def _free_slab(**kw):
    base = dict(m=[10.0, 10.0], L=[0.5, 0.5], c_l=[1.0, 1.0], c_r=[1.0, 1.0], k_phi=[1e5], c_phi=[0.0], f_n=100.0)
    return st.slab_from_free(**{**base, **kw})


def _free_ballasted(**kw):
    base = dict(m=[20.0], L=[0.4], c_l=[0.0], c_r=[0.0], k_phi=[], c_phi=[], d_l=[0.0], d_r=[0.0],
                f_n1=117.0, f_n2=465.0, f_anti=243.0)
    return st.ballasted_from_free(**{**base, **kw})


@pytest.mark.parametrize(("call", "words"), [
    # overflow at huge values: a LinAlgError, NaN or a raw OverflowError later
    (lambda: st.slab_track(kv=1.7e308), ("kv must be from", "N/m")),
    (lambda: st.ballasted_track().replace(eta_pad=1e308), ("eta_pad must be from",)),
    (lambda: st.slab_track(E=5e-324), ("E must be from",)),  # tiny: a ZeroDivisionError
    (lambda: st.Wheel(primary_damping=1e308), ("primary_damping must be from", "N s/m")),
    (lambda: st.Wheel(hertz_constant=1e308), ("hertz_constant must be from",)),
    (lambda: st.Wheel.from_radii(rail_radius=5e-324), ("rail_radius must be from",)),  # named hertz_constant
    (lambda: st.Wheel.from_radii(E=1e308), ("E must be from",)),
    (lambda: _free_slab(k_phi=[1e308]), ("k_phi[0] must be from",)),  # an SVD that did not converge
    (lambda: _free_ballasted(m=[1e308]), ("m[0] must be from",)),  # named k[0]
    (lambda: _free_ballasted(m=[1e12]), ("m, L, f_n1, f_n2 and f_anti give k[0]",)),
    (lambda: _free_slab(m=[0.5, 0.5], L=[3e9, 3e9]), ("m, L and f_n give J[0]",)),
    (lambda: st.paper_consistency_report(f_n=2e153), ("f_n must be at most",)),  # a raw OverflowError
    (lambda: st.continuous_foundation_receptance(SLAB, [10.0], k_f=-1e308), ("k_f must be at most",)),  # NaN
    (lambda: st.continuous_foundation_receptance(SLAB, [10.0], k_f=1e7, x=1e308), ("x must be from",)),  # NaN
    (lambda: st.third_octave_bands(100.0, 1.7e308), ("hi must be from",)),  # an infinite upper edge
    (lambda: st.Wheel().receptance(1e-308), ("f must be at least 1e-12 Hz",)),  # a complex division by zero
    (lambda: st.roughness_from_spectrum(20.0).at_speed(5e-324), ("speed must be from",)),  # ZeroDivisionError
    # sizes that were a MemoryError
    (lambda: SLAB.cell(10**12), ("supports_per_period must be at most",)),
    (lambda: st.PeriodicCell.uniform(SLAB, 2**64), ("supports_per_period must be at most",)),
    (lambda: st.TruncatedTrack(SLAB, 4, f_max=1e12), ("f_max must be from",)),  # 3.6 TiB asked
])
def test_values_beyond_the_physics_are_refused_naming_the_parameter(call, words):
    refused(call, BadInput, *words, cpu=ONE_SECOND)


@pytest.mark.parametrize(("call", "words"), [
    # flags and mappings read by their truth value: "ambiguous truth value"
    (lambda: st.load_boundary("unread.json", check=np.ones((2, 2))), ("check must be True or False",)),
    (lambda: st.TruncatedTrack(SLAB, 4, changes=np.ones((2, 2))), ("changes must be a mapping",)),
    (lambda: _free_slab().is_passive([100.0], tol=10**400), ("tol must be a finite real number",)),
    # shapes: a broadcast error or an IndexError
    (lambda: st.InfiniteTrack(SLAB).receptance(np.ones((1, 2, 2)), 0.1, [0.2]), ("f must be", "1-D")),
    (lambda: st.InfiniteTrack(SLAB).receptance([100.0], 0.1, []), ("x must hold at least one value",)),
    (lambda: st.FrequencyTable(f=[[50.0], [200.0, 400.0]], values=[1.0, 2.0], quantity="stiffness"), ("f must be",)),
    (lambda: st.paper_consistency_report(f_n2_candidates=np.ones((2, 2))), ("f_n2_candidates must be a 1-D",)),
])
def test_flags_mappings_and_shapes_are_refused_naming_the_parameter(call, words):
    refused(call, BadInput, *words, cpu=ONE_SECOND)


def test_records_hold_their_numbers_as_floats_and_refuse_integers_beyond_them():
    summary = st.ErrorSummary(median=2**64, max=0.1, per_element={})
    assert isinstance(summary.median, float) and summary.median == 2.0**64  # was held as an int numpy cannot read
    refused(lambda: st.ErrorSummary(median=10**400, max=0.1, per_element={}), BadInput, "ErrorSummary.median")
    kernels = st.moving_green_kernels(SLAB, 20.0, dt=1e-4, memory=0.005, elements_per_bay=4)
    fields = {f.name: getattr(kernels, f.name) for f in __import__("dataclasses").fields(kernels)}
    refused(lambda: type(kernels)(**{**fields, "elements_per_bay": 2**64}), BadInput, "elements_per_bay",
            "64 bits")


def test_a_wheel_defect_that_does_not_fit_the_wheel_is_named_as_the_wheels_argument():
    refused(lambda: st.Wheel(defects=[st.WheelFlat(length=0.5, shape="new")]), BadInput, "defects[0]", "depth")


def test_given_kernels_that_do_not_fit_name_what_differs():
    kernels = st.moving_green_kernels(SLAB, 20.0, dt=1e-4, memory=0.005, elements_per_bay=4)
    refused(lambda: st.moving_green_response(SLAB, st.Wheel(), speed=0.5, dt=1e-4, duration=0.03, kernels=kernels),
            BadInput, "speed=0.5", "the kernels'")
    refused(lambda: st.moving_green_response(SLAB, st.Wheel(), speed=20.0, dt=1e-4, duration=0.03, memory=1e-308,
                                             elements_per_bay=4), BadInput, "memory")


def test_a_contact_a_hair_from_a_node_is_the_nodes():
    model = st.TruncatedTrack(SLAB, 2, elements_per_bay=4)
    assert model.local_flexibility(np.array([1e-308, 1e-300]))[0] == 0.0  # was NaN (1 / a^3 overflowed)
    run = dict(speed=0.0, dt=5e-5, duration=0.03)
    at_node = st.wheel_rail_response(model, st.Wheel(), x=0.0, **run).force
    np.testing.assert_allclose(st.wheel_rail_response(model, st.Wheel(), x=[1e-308], **run).force, at_node)
    refused(lambda: st.wheel_rail_response(model, st.Wheel(), compiled=np.ones((2, 2)), **run), BadInput,
            "compiled must be True or False")


def test_the_convolution_refuses_a_memory_it_cannot_hold_before_allocating_it():
    """memory / dt = 1e9 lags: the frequency grid alone was 8 GB, the receptances 24 GB (the long profile's
    worker was killed by the kernel's OOM killer)."""
    refused(lambda: st.convolution_response(SLAB, st.Wheel(), x=0.0, dt=1e-5, duration=0.03, memory=1e4),
            InputError, "memory=10000.0", "frequencies", cpu=ONE_SECOND)


# --- the long profile's second round (stop 44): each drawn once by Hypothesis, kept here by class ----
def _fit():
    return st.fit_equivalent(SLAB, "slab", n_bars=2, band=(3.0, 300.0), n_starts=1, max_nfev=20, error_df=30.0)


@pytest.mark.parametrize(("call", "words"), [
    # tiny and huge values: NaN, a ZeroDivisionError or an OverflowError later
    (lambda: st.contact_filter([5e-324], 0.006), ("wavelength must be from",)),  # nan
    (lambda: st.corrugation(20.0, 0.05, 1e308), ("amplitude must be from",)),  # inf then nan
    (lambda: st.corrugation(20.0, 1e12, 1e-6), ("wavelength must be from",)),  # named period
    (lambda: st.corrugation(1000.0, 1e-7, 1e-6), ("wavelength must be at least",)),  # 10 GHz, named frequencies
    (lambda: st.corrugation(20.0, 0.05, 1e-6).sampled(1e308, 10), ("dt must be from",)),  # nan
    (lambda: st.corrugation(20.0, 0.05, 1e-6).sampled(1e-308, 10), ("dt must be from",)),  # OverflowError
    (lambda: st.corrugation(20.0, 0.05, 1e-6).along_rail(-1e308, 2.0), ("start must be from",)),  # named x
    (lambda: st.corrugation(20.0, 0.05, 1e-6).along_rail(0.0, 1e308), ("length must be from",)),  # OverflowError
    (lambda: st.corrugation(20.0, 0.05, 1e-6).along_rail(0.0, 7e-6, fade=6e-8), ("length=",)),  # named x and r
    (lambda: st.corrugation(20.0, 0.05, 1e-6, phase=float("inf")), ("phase must be finite",)),  # named phases
    (lambda: st.corrugation(20.0, 0.05, 1e-6).scaled(1e300), ("factor=",)),  # named amplitudes
    (lambda: st.roughness_from_spectrum(100.0, [5e-324], [-50.0]), ("wavelengths must be band centres from",)),
    (lambda: st.unit_cell_frequencies(m=5e-324, J=0.1, L=0.4, k=1e7), ("m must be from",)),  # nan
    (lambda: st.unit_cell_frequencies(m=1.0, J=0.1, L=1e308, k=1e7), ("L must be from",)),  # a LinAlgError
    (lambda: st.moving_green_response(st.slab_track(damping="viscous"), st.Wheel(), speed=5e-324, dt=1e-4,
                                      duration=0.005, ramp=0.002, memory=0.005, elements_per_bay=4),
     ("speed must be from",)),  # ZeroDivisionError
    (lambda: st.TruncatedTrack(SLAB, 2, f_max=5e-324), ("f_max must be from",)),  # IndexError
    (lambda: st.WavenumberSettings(dx=4.6e305), ("dx must be from",)),  # nan receptance
    (lambda: st.convolution_response(SLAB, st.Wheel(), x=0.0, dt=1e12, duration=1e12), ("dt must be from",)),
    (lambda: st.convolution_response(SLAB, st.Wheel(), x=0.0, dt=0.5, duration=1e12),  # 14.6 TiB asked
     ("duration=1000000000000.0 s", "record")),
    # strings never numbers, and work guards
    (lambda: st.moving_green_kernels(st.slab_track(damping="viscous"), 20.0, dt=1e-4, memory=0.005,
                                     elements_per_bay=""), ("elements_per_bay must be an integer",)),  # int('')
    (lambda: st.cached_fit(SLAB, "slab", n_bars=2, band=(3.0, 300.0), n_starts=2**64), ("n_starts=",)),  # OOM
    (lambda: st.semi_infinite_receptance(SLAB, [100.0], method="wavenumber",
                                         settings=st.WavenumberSettings(beta_max=4e5)), ("terms per frequency",)),
    (lambda: st.WindowTrack(st.slab_track(damping="viscous"), behind=2, ahead=3, elements_per_bay=4,
                            system=st.load_boundary("tests/data/boundary_slab_viscous_24.json")).model_at(2**64, 2, 3),
     ("offset must be at most",)),  # named bay
])
def test_the_long_profiles_values_are_refused_at_once_naming_the_parameter(call, words):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a short memory or coarse mesh, warned of by design
        refused(call, BadInput, *words, cpu=ONE_SECOND)


def test_records_refuse_fields_of_another_kind_or_shape():
    import dataclasses
    fit = _fit()
    boundary = st.load_boundary("tests/data/boundary_slab_viscous_24.json")
    for call, words in [(lambda: dataclasses.replace(fit, layout=-0.0), "FitResult.layout must be one of"),
                        (lambda: dataclasses.replace(boundary, band=["0.3"]), "BroadbandBoundary.band must be a tuple"),
                        (lambda: st.MatrixSystem(np.eye(2), np.zeros((2, 2)), np.eye(2), dofs=-0.0), "dofs must be")]:
        refused(call, BadInput, words)
    assert type(st.WavenumberSettings(beta_max=2**20).beta_max) is float  # not an int numpy may read as an object
    decay = st.track_decay_rate(SLAB, band=(100.0, 400.0), df=20.0)
    refused(lambda: dataclasses.replace(decay, centres=np.array([True])), BadInput, "TrackDecayRate.decay_rate")
    model = st.TruncatedTrack(SLAB, 2, elements_per_bay=4)
    run = st.wheel_rail_response(model, st.Wheel(), dt=1e-4, duration=0.01, ramp=0.002)
    refused(lambda: dataclasses.replace(run, force=np.float64(-0.0)), BadInput, "ContactResponse.force")
    refused(lambda: dataclasses.replace(run, t=np.float64(0.0)), BadInput, "ContactResponse.t")


def test_a_receptance_beyond_the_meshs_probe_is_computed_and_said_to_be_unchecked():
    model = st.TruncatedTrack(SLAB, 2, elements_per_bay=4)
    with pytest.warns(RuntimeWarning, match="measured up to 20000 Hz only"):
        alpha = model.receptance([20001.0], 0.0)  # was a refusal naming f_max, not f
    assert np.isfinite(alpha).all()


@pytest.mark.parametrize(("call", "words"), [
    (lambda: st.RandomTrack(BALLASTED, 0, 3, seed=2**64), ("seed must be below 2**64",)),
    (lambda: st.WavenumberSettings(j_max=2**64), ("j_max must be at most",)),  # held as an object
    (lambda: st.WavenumberSettings(dx=0.25), ("dx must be from",)),  # a receptance that is not passive
    (lambda: st.WavenumberSettings(dx=1e-308), ("dx must be from 0.0001",)),  # a NaN receptance
    (lambda: st.semi_infinite_receptance(SLAB, [100.0], method="wavenumber", dx=1e-6),
     ("dx must be from 0.0001",)),  # a slope that lost its digits: 25 % off the exact receptance
    (lambda: st.export_system(st.paper_table4(), "unused.json", track_damping=np.array([])),
     ("track_damping must be one of",)),  # numpy's truth-value error
    (lambda: st.WheelFlat(1e308, shape="rounded"), ("length must be from",)),  # an OverflowError when used
    (lambda: st.cached_fit(SLAB, "slab", n_bars=1 + 1j), ("n_bars",)),  # named "an argument of type complex"
    (lambda: st.corrugation(1e-308, 0.05, 1e-6), ("speed must be from",)),  # named wavelength
    (lambda: st.fit_equivalent(SLAB, "slab", n_bars=2, band=(3.0, 300.0), error_df=5e-324), ("error_df=",)),
    (lambda: st.semi_infinite_receptance(SLAB, [100.0], method=np.ones((2, 2))), ("method must be one of",)),
    (lambda: st.FETrack(SLAB, 0, 0), ("n_left = n_right = 0",)),  # named the ends only
    (lambda: st.WavenumberSettings(beta_max=1e308), ("beta_max/dbeta",)),  # an OverflowError counting the grid
    (lambda: st.moving_green_kernels(st.slab_track(damping="viscous"), 20.0, dt=1e-4, memory=0.005, x=-1e308,
                                     elements_per_bay=4), ("x must be from",)),  # an OverflowError
])
def test_the_long_profiles_third_round_is_refused_naming_the_parameter(call, words):
    refused(call, BadInput, *words, cpu=ONE_SECOND)


def test_tuples_of_a_kind_refuse_entries_of_another():
    import dataclasses
    fit = _fit()
    refused(lambda: dataclasses.replace(fit, free_parameters=[0.3]), BadInput, "FitResult.free_parameters")
    run = st.wheel_rail_response(st.TruncatedTrack(SLAB, 2, elements_per_bay=4), st.Wheel(), dt=1e-4, duration=0.01,
                                 ramp=0.002)
    refused(lambda: dataclasses.replace(run, wheels=["0.3"]), BadInput, "ContactResponse.wheels")


def test_a_long_period_is_sampled_without_its_whole_periods_fft():
    """A period of 9348 s at 0.1 ms is 9e7 steps: its FFT asked 1.5 GB (a MemoryError); now the cosines, bounded."""
    r = st.corrugation(20.0, 0.05, 1e-6)
    long = st.Roughness(r.frequencies, r.amplitudes, r.phases, r.speed, period=9348.125)
    np.testing.assert_allclose(long.sampled(1e-4, 10), r.sampled(1e-4, 10), atol=1e-18)
    fit = _fit()
    assert dataclasses_replace(fit, free_parameters=[]).free_parameters == ()  # a list held as the tuple it is


def dataclasses_replace(record, **fields):
    import dataclasses
    return dataclasses.replace(record, **fields)


def test_the_command_line_reads_no_underscored_numbers(tmp_path, capsys):
    from semitrack.cli import main
    from semitrack.model.trackfile import example_path
    assert main(["fit", str(example_path("slab")), "--bars", "1_0", "--layout", "slab", "--band", "3", "300",
                 "-o", str(tmp_path / "f.json"), "--quiet"]) == 2  # Python's int("1_0") is 10: a 10-bar fit
    assert "invalid integer value: '1_0'" in capsys.readouterr().err
    assert main(["receptance", str(example_path("slab")), "--fmin", "1_00", "-o", str(tmp_path / "r.csv")]) == 2
    assert "invalid number value: '1_00'" in capsys.readouterr().err


def test_the_default_mesh_serves_frequencies_below_1_hz_and_names_f_above_its_range():
    """``f=0.5`` without elements_per_bay was refused naming f_max, a parameter the caller never gave (the
    property suite, seed 31); the 1-Hz mesh serves it. Above 20 kHz the refusal names f."""
    low = st.fe_central_receptance(SLAB, [0.5], n_bays=10)
    assert low.shape == (1, 2, 2) and np.all(np.isfinite(low))
    assert np.allclose(low[0], st.fe_central_receptance(SLAB, [0.5, 1.0], n_bays=10)[0], rtol=1e-12)  # the 1-Hz mesh
    refused(lambda: st.fe_semi_infinite_receptance(SLAB, [3e4]), InputError, "f must be from 0 to 20000",
            "elements_per_bay", cpu=ONE_SECOND)


def test_a_given_mesh_checks_frequencies_below_1_hz_against_its_1_hz_probe():
    """``FETrack.receptance(f=0.5)`` on a model with its own mesh was refused naming f_max (the property
    suite, seed 61): the mesh check probed at 0.5 Hz, below the probes' first. A mesh that resolves 1 Hz
    resolves anything lower."""
    model = st.FETrack(SLAB, 2, 2, "pinned", "pinned", elements_per_bay=8)
    low = model.receptance(0.5)
    assert low.shape == (2, 2) and np.all(np.isfinite(low))
    assert np.allclose(model.receptance([0.5, 1.0])[0], low, rtol=1e-12)


def test_a_roughness_line_beyond_1_ghz_is_refused_naming_frequencies():
    """``frequencies=1e308`` over a 2001-s period was accepted, and its signal was NaN (the property suite,
    seed 61): f times the period overflowed, so the whole-multiple check passed on NaN."""
    refused(lambda: st.Roughness(frequencies=[1e308], amplitudes=[1e-6], phases=[0.0], speed=20.0, period=2001.0),
            InputError, "frequencies must be positive and at most 1e+09 Hz", cpu=ONE_SECOND)
    line = st.Roughness(frequencies=[1e9], amplitudes=[1e-6], phases=[0.0], speed=20.0, period=1.0)
    assert np.all(np.isfinite(line.sampled(1e-9, 10)))


def test_a_corrugation_on_the_shortest_wavelength_is_taken_or_refused_naming_wavelength():
    for speed in np.linspace(1.0, 1000.0, 400):  # speed / (speed / 1e9) rounds above 1e9 at some speeds
        try:
            st.corrugation(float(speed), float(speed) / 1e9, 1e-6)
        except st.BadInput as err:
            assert str(err).startswith("wavelength must be at least"), err
