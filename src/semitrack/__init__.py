"""semitrack: receptance of a semi-infinite periodic railway track and its equivalent systems.

A research compendium package reproducing and extending the paper "Receptance of a
semi-infinite periodic railway track and an equivalent multi-rigid body system for use in
truncated track models". SI units; frequencies in Hz at the API.

The flat API (``st.fit_equivalent``, ``st.TruncatedTrack``, ...) is loaded on first use (PEP 562):
``import semitrack`` itself imports nothing heavy, so that the command line can answer Ctrl-C
from its first moment, and a name costs its module's import only when it is used.
"""

__version__ = "0.2.0"

#: Every public name: ``{name: (module, attribute in it)}``, in the order of ``__all__``.
_EXPORTS: dict[str, tuple[str, str]] = {
    "BadInput": ("base.errors", "BadInput"),
    "PAPER_FIT_BANDS": ("base.paper_values", "FIT_BANDS"),
    "PAPER_GRID": ("base.paper_values", "PAPER_GRID"),
    "BroadbandBoundary": ("boundary.fitting", "BroadbandBoundary"),
    "fit_boundary": ("boundary.fitting", "fit_boundary"),
    "cached_boundary": ("boundary.cache", "cached_boundary"),
    "load_boundary": ("boundary.io", "load_boundary"),
    "save_boundary": ("boundary.io", "save_boundary"),
    "export_boundary": ("boundary.io", "export_boundary"),
    "BallastedEquivalent": ("equivalent.systems", "BallastedEquivalent"),
    "CentralResponse": ("methods.receptance", "CentralResponse"),
    "EquivalentSystem": ("equivalent.systems", "EquivalentSystem"),
    "MechanicalSystem": ("equivalent.mechanical", "MechanicalSystem"),
    "MatrixSystem": ("equivalent.mechanical", "MatrixSystem"),
    "ErrorSummary": ("equivalent.metrics", "ErrorSummary"),
    "FETrack": ("fe.models", "FETrack"),
    "InfiniteTrack": ("methods.infinite", "InfiniteTrack"),
    "TrackDecayRate": ("methods.decay", "TrackDecayRate"),
    "track_decay_rate": ("methods.decay", "track_decay_rate"),
    "ISO3095_TDR_LIMIT": ("methods.decay", "ISO3095_TDR_LIMIT"),
    "FitResult": ("equivalent.fitting", "FitResult"),
    "FrequencyCurve": ("model.curves", "FrequencyCurve"),
    "FrequencyTable": ("model.curves", "FrequencyTable"),
    "FrequencyFunction": ("model.curves", "FrequencyFunction"),
    "StandardLinearSolid": ("model.curves", "StandardLinearSolid"),
    "load_frequency_table": ("model.tablefile", "load_frequency_table"),
    "PeriodicCell": ("model.tracks", "PeriodicCell"),
    "QUANTITIES": ("methods.features", "QUANTITIES"),
    "Slab": ("model.slab", "Slab"),
    "SlabEquivalent": ("equivalent.systems", "SlabEquivalent"),
    "Track": ("model.tracks", "Track"),
    "TrackFileError": ("model.trackfile", "TrackFileError"),
    "TruncatedTrack": ("fe.models", "TruncatedTrack"),
    "WindowTrack": ("fe.window", "WindowTrack"),
    "WavenumberSettings": ("methods.wavenumber", "WavenumberSettings"),
    "Wheel": ("model.wheel", "Wheel"),
    "WheelFlat": ("model.wheel_defects", "WheelFlat"),
    "WheelPolygon": ("model.wheel_defects", "WheelPolygon"),
    "wheel_centre_path": ("model.centre_path", "wheel_centre_path"),
    "contact_semi_length": ("model.contact_filter", "contact_semi_length"),
    "contact_filter": ("model.contact_filter", "contact_filter"),
    "contact_filtered": ("model.contact_filter", "contact_filtered"),
    "Bogie": ("model.vehicle", "Bogie"),
    "convolution_response": ("interaction.infinite_convolution", "convolution_response"),
    "moving_green_response": ("interaction.moving_green", "moving_green_response"),
    "moving_green_kernels": ("interaction.moving_green", "moving_green_kernels"),
    "MovingKernels": ("fe.kernels", "MovingKernels"),
    "DippedWeld": ("model.irregularity", "DippedWeld"),
    "RailProfile": ("model.irregularity", "RailProfile"),
    "WheelGroup": ("model.vehicle", "WheelGroup"),
    "default_fit_frequencies": ("equivalent.fitting", "default_fit_frequencies"),
    "fe_central_receptance": ("fe.models", "fe_central_receptance"),
    "fe_semi_infinite_receptance": ("fe.models", "fe_semi_infinite_receptance"),
    "fit_characteristic_frequencies": ("equivalent.fitting", "fit_characteristic_frequencies"),
    "fit_equivalent": ("equivalent.fitting", "fit_equivalent"),
    "load_track_toml": ("model.trackfile", "load_track_toml"),
    "load_track_file": ("model.trackfile", "load_track_file"),
    "load_vehicle_toml": ("model.vehiclefile", "load_vehicle_toml"),
    "vehicle_to_toml": ("model.vehiclefile", "vehicle_to_toml"),
    "load_roughness_spectrum": ("model.seriesfile", "load_roughness_spectrum"),
    "load_rail_profile": ("model.seriesfile", "load_rail_profile"),
    "parameter_table": ("model.tracks", "parameter_table"),
    "ballasted_from_free": ("equivalent.constraints", "ballasted_from_free"),
    "ballasted_track": ("model.tracks", "ballasted_track"),
    "cached_fit": ("equivalent.cache", "cached_fit"),
    "cell_frequencies": ("equivalent.constraints", "cell_frequencies"),
    "central_response": ("methods.receptance", "central_response"),
    "characteristic_frequencies": ("methods.features", "characteristic_frequencies"),
    "continuous_foundation_receptance": ("methods.continuous", "continuous_foundation_receptance"),
    "error_band_grid": ("equivalent.metrics", "error_band_grid"),
    "error_summary": ("equivalent.metrics", "error_summary"),
    "example_track": ("model.trackfile", "example_track"),
    "export_system": ("equivalent.io", "export_system"),
    "load_matrix_system": ("equivalent.exchange", "load_matrix_system"),
    "find_extrema": ("methods.features", "find_extrema"),
    "load_system_csv": ("equivalent.io", "load_system_csv"),
    "load_system_json": ("equivalent.io", "load_system_json"),
    "load_system_mat": ("equivalent.io", "load_system_mat"),
    "paper_consistency_report": ("paper.systems", "paper_consistency_report"),
    "paper_frequency_table": ("paper.frequencies", "paper_frequency_table"),
    "paper_table4": ("paper.systems", "paper_table4"),
    "paper_table7": ("paper.systems", "paper_table7"),
    "point_receptance": ("methods.receptance", "point_receptance"),
    "receptance_errors": ("equivalent.metrics", "receptance_errors"),
    "response_curves": ("methods.features", "response_curves"),
    "semi_infinite_receptance": ("methods.receptance", "semi_infinite_receptance"),
    "slab_from_free": ("equivalent.constraints", "slab_from_free"),
    "slab_track": ("model.tracks", "slab_track"),
    "unit_cell_frequencies": ("equivalent.constraints", "unit_cell_frequencies"),
    "wheel_rail_force": ("methods.wheelrail", "wheel_rail_force"),
    "ContactResponse": ("interaction.response", "ContactResponse"),
    "ContactTransfer": ("interaction.transfer", "ContactTransfer"),
    "contact_transfer": ("interaction.transfer", "contact_transfer"),
    "wheel_rail_response": ("interaction.fe_model", "wheel_rail_response"),
    "ISO3095_ROUGHNESS_LIMIT": ("model.roughness", "ISO3095_ROUGHNESS_LIMIT"),
    "Roughness": ("model.roughness", "Roughness"),
    "corrugation": ("model.roughness", "corrugation"),
    "roughness_from_spectrum": ("model.roughness", "roughness_from_spectrum"),
    "third_octave_bands": ("base.bands", "third_octave_bands"),
    "nominal_bands": ("base.bands", "nominal_bands"),
    "HystereticDampingWarning": ("base.notices", "HystereticDampingWarning"),
    "ImplausibleValueWarning": ("base.notices", "ImplausibleValueWarning"),
    "RandomTrack": ("model.random_track", "RandomTrack"),
    "random_track": ("model.random_track", "random_track"),
    "run_study": ("studies.runner", "run_study"),
}

__all__ = list(_EXPORTS)


def __getattr__(name: str):
    """Load a public name from its module on first use, then keep it here."""
    try:
        module, attribute = _EXPORTS[name]
    except KeyError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    value = getattr(__import__(f"{__name__}.{module}", fromlist=[attribute]), attribute)  # not importlib: its
    # import (functools, collections) was half of the console script's start, before Ctrl-C is answered
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
