"""Numbers transcribed from the paper, in one place.

Everything the package takes from the paper's text and tables lives here, so that code, tests,
benchmarks and the book read the same value and a correction is made once. The modules that
use them (track presets, the wavenumber method's default settings, the paper's equivalent
systems, the audits) import from here. Values are SI; frequencies in Hz.
"""

from __future__ import annotations

__all__ = ["FIT_BANDS", "TABLE4_FIT_FREQUENCIES", "TABLE7_FIT_FREQUENCIES"]

#: The frequency band (Hz) over which the paper fits and judges each layout's equivalent
#: system: 3-900 Hz for the slab track (Sec. 4.4, Table 4), 3-750 Hz for the ballasted track
#: (Sec. 5.2, Table 7).
FIT_BANDS: dict[str, tuple[float, float]] = {"slab": (3.0, 900.0), "ballasted": (3.0, 750.0)}

#: The pre-selected frequencies (Hz) of the paper's fits (Sec. 4.4 for Table 4, Sec. 5.2 for Table 7).
TABLE4_FIT_FREQUENCIES = (3.0, 15.0, 87.0, 117.0, 183.0, 207.0, 333.0, 597.0, 897.0)
TABLE7_FIT_FREQUENCIES = (3.0, 15.0, 27.0, 87.0, 117.0, 167.0, 217.0, 243.0, 277.0, 327.0, 377.0,
                          427.0, 457.0, 489.0, 517.0, 567.0, 617.0, 800.0)
