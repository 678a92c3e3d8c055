"""semitrack: receptance of a semi-infinite periodic railway track and its equivalent systems.

A research compendium package reproducing and extending the paper "Receptance of a
semi-infinite periodic railway track and an equivalent multi-rigid body system for use in
truncated track models". SI units; frequencies in Hz at the API.
"""

from .base.paper_values import FIT_BANDS as PAPER_FIT_BANDS
from .base.paper_values import PAPER_GRID
from .boundary.fitting import BroadbandBoundary, fit_boundary
from .boundary.io import load_boundary, save_boundary
from .equivalent.cache import cached_fit
from .equivalent.constraints import ballasted_from_free, cell_frequencies, slab_from_free, unit_cell_frequencies
from .equivalent.fitting import FitResult, default_fit_frequencies, fit_characteristic_frequencies, fit_equivalent
from .equivalent.io import export_system, load_system_csv, load_system_json, load_system_mat
from .equivalent.metrics import ErrorSummary, error_band_grid, error_summary, receptance_errors
from .equivalent.systems import BallastedEquivalent, EquivalentSystem, SlabEquivalent
from .fe.models import FETrack, TruncatedTrack, fe_central_receptance, fe_semi_infinite_receptance
from .methods.continuous import continuous_foundation_receptance
from .methods.features import QUANTITIES, characteristic_frequencies, find_extrema, response_curves
from .methods.receptance import CentralResponse, central_response, point_receptance, semi_infinite_receptance
from .methods.wavenumber import WavenumberSettings
from .model.trackfile import TrackFileError, load_track_toml
from .model.tracks import PeriodicCell, Track, ballasted_track, parameter_table, slab_track
from .paper.frequencies import paper_frequency_table
from .paper.systems import paper_consistency_report, paper_table4, paper_table7

__version__ = "0.1.0"

__all__ = [
    "PAPER_FIT_BANDS", "PAPER_GRID",
    "BroadbandBoundary", "fit_boundary", "load_boundary", "save_boundary",
    "BallastedEquivalent", "CentralResponse", "EquivalentSystem", "ErrorSummary", "FETrack", "FitResult",
    "PeriodicCell", "QUANTITIES", "SlabEquivalent", "Track", "TrackFileError", "TruncatedTrack",
    "WavenumberSettings", "default_fit_frequencies", "fe_central_receptance", "fe_semi_infinite_receptance",
    "fit_characteristic_frequencies", "fit_equivalent", "load_track_toml", "parameter_table",
    "ballasted_from_free", "ballasted_track", "cached_fit", "cell_frequencies", "central_response",
    "characteristic_frequencies", "continuous_foundation_receptance", "error_band_grid",
    "error_summary", "export_system", "find_extrema", "load_system_csv", "load_system_json",
    "load_system_mat", "paper_consistency_report", "paper_frequency_table", "paper_table4",
    "paper_table7", "point_receptance", "receptance_errors", "response_curves",
    "semi_infinite_receptance", "slab_from_free", "slab_track", "unit_cell_frequencies",
]
