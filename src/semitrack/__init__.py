"""semitrack: receptance of a semi-infinite periodic railway track and its equivalent systems.

A research compendium package reproducing and extending the paper "Receptance of a
semi-infinite periodic railway track and an equivalent multi-rigid body system for use in
truncated track models". SI units; frequencies in Hz at the API.
"""

from .continuous import continuous_foundation_receptance
from .features import QUANTITIES, characteristic_frequencies, find_extrema, response_curves
from .paper import paper_frequency_table
from .receptance import CentralResponse, central_response, point_receptance, semi_infinite_receptance
from .tracks import PeriodicCell, Track, ballasted_track, slab_track
from .wavenumber import WavenumberSettings

__version__ = "0.1.0"

__all__ = [
    "CentralResponse", "PeriodicCell", "QUANTITIES", "Track", "WavenumberSettings",
    "ballasted_track", "central_response", "characteristic_frequencies",
    "continuous_foundation_receptance", "find_extrema", "paper_frequency_table",
    "point_receptance", "response_curves", "semi_infinite_receptance", "slab_track",
]
