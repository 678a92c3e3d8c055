"""Numbers transcribed from the paper, in one place.

Everything the package takes from the paper's text and tables lives here, so that code, tests,
benchmarks and the book read the same value and a correction is made once. The modules that
use them (track presets, the wavenumber method's default settings, the paper's equivalent
systems, the audits) import from here. Values are SI; frequencies in Hz.

Contents, in the order of the paper:

* :data:`TABLE2_RAIL`, :data:`TABLE2_SLAB`, :data:`TABLE5_BALLASTED`: the track parameters;
  :data:`PAD_LENGTH` for the paper's ``kphi = kv b^2 / 12``.
* :data:`PAPER_BETA_MAX`, :data:`PAPER_DBETA`, :data:`PAPER_J_MAX`, :data:`PAPER_DX` and
  :data:`PAPER_GRID` (with :data:`PAPER_GRID_BAND`, :data:`PAPER_GRID_STEP`): the numerical
  settings and frequency grid of Sec. 4.1.
* :data:`TABLE3_SLAB_FREQUENCIES`, :data:`TABLE6_BALLASTED_FREQUENCIES`: the characteristic
  frequencies of Tables 3 and 6 and of Sec. 4.2-4.3 and 5.1-5.2.
* :data:`FIT_BANDS`, :data:`TABLE4_FIT_FREQUENCIES`, :data:`TABLE7_FIT_FREQUENCIES`,
  :data:`CONSTRAINT_FREQUENCIES`: how the paper fitted its equivalent systems.
* :data:`TABLE4`, :data:`TABLE7` and their rounding half-widths :data:`TABLE4_HALF_ULP`,
  :data:`TABLE7_HALF_ULP`: the printed equivalent systems.
"""

from __future__ import annotations

from types import MappingProxyType

import numpy as np

__all__ = [
    "TABLE2_RAIL", "TABLE2_SLAB", "TABLE5_BALLASTED", "PAD_LENGTH", "PAPER_SLAB_DECAY_RATE", "PAPER_DECAY_DISTANCE",
    "PAPER_BETA_MAX", "PAPER_DBETA", "PAPER_J_MAX", "PAPER_DX", "PAPER_GRID", "PAPER_GRID_BAND", "PAPER_GRID_STEP",
    "TABLE3_SLAB_FREQUENCIES", "TABLE6_BALLASTED_FREQUENCIES",
    "FIT_BANDS", "TABLE4_FIT_FREQUENCIES", "TABLE7_FIT_FREQUENCIES", "CONSTRAINT_FREQUENCIES",
    "TABLE4", "TABLE4_HALF_ULP", "TABLE7", "TABLE7_HALF_ULP", "TABLE7_S1_TRANSPOSED",
]

# ------------------------------------------------------------------------------------------
# Tracks (Tables 2 and 5). Read-only mappings: a preset overrides by copying, never in place.

#: The rail of both tracks (Table 2): density (kg/m^3), Young's and shear modulus (N/m^2),
#: area (m^2), second moment of area (m^4), shear coefficient (-) and loss factor (-).
TABLE2_RAIL = MappingProxyType(dict(
    rho=7850.0, E=2.1e11, G=0.81e11, A=7.69e-3, I=30.55e-6, kappa=0.4, eta_rail=0.01,
))

#: The slab track (Table 2): the rail, pad stiffness kv (N/m) and kphi (N m/rad), pad loss
#: factor (-) and fastener spacing (m). The paper states ``kphi = kv b^2 / 12`` with the pad
#: length b = :data:`PAD_LENGTH` and prints it rounded, 2.83e5 N m/rad, which is the value here.
TABLE2_SLAB = MappingProxyType(dict(
    TABLE2_RAIL, kv=5.44e7, kphi=2.83e5, eta_pad=0.1, spacing=0.65,
))

#: The ballasted track (Tables 2 and 5): the rail, pad (N/m, N m/rad, -), sleeper spacing (m),
#: mass of half a sleeper (kg), ballast stiffness under one rail seat (N/m) and its loss factor (-).
TABLE5_BALLASTED = MappingProxyType(dict(
    TABLE2_RAIL, kv=3.5e8, kphi=1.82e6, eta_pad=0.1, spacing=0.6, sleeper_mass=150.0, kb=100e6,
    eta_ballast=0.3,
))

#: Length b of the slab track's rail pad (m), from which the paper derives kphi (Sec. 4).
PAD_LENGTH = 0.25

#: The decay rate the paper's Sec. 1 cites for slab tracks above a few hundred hertz (dB/m; from its
#: ref. [5]), and the distance it derives from it for 20 dB of decay (m): its case for long models.
PAPER_SLAB_DECAY_RATE = 0.5
PAPER_DECAY_DISTANCE = 40.0

# ------------------------------------------------------------------------------------------
# The wavenumber method's settings and the frequency grid (Sec. 4.1).

#: Half-width of the wavenumber range, 5000 x 0.0025 x 2 pi = 78.5 rad/m.
PAPER_BETA_MAX = 5000 * 0.0025 * 2 * np.pi
#: Wavenumber step, 2 pi x 0.0025 rad/m.
PAPER_DBETA = 2 * np.pi * 0.0025
#: The sum over j runs over |j| <= 20.
PAPER_J_MAX = 20
#: Step of the finite-difference slopes (m), pi / beta_max.
PAPER_DX = 0.04

#: The band (Hz) and step (Hz) of the paper's frequency grid: 3, 9, ..., 2997 Hz.
PAPER_GRID_BAND = (3.0, 3000.0)
PAPER_GRID_STEP = 6.0
#: The paper's frequency grid itself (500 frequencies, Hz), read-only.
PAPER_GRID = np.arange(*PAPER_GRID_BAND, PAPER_GRID_STEP)
PAPER_GRID.setflags(write=False)

# ------------------------------------------------------------------------------------------
# Characteristic frequencies (Tables 3 and 6, Sec. 4.2-4.3 and 5.1-5.2).
# (paper frequency in Hz, quantity, kind, where the paper states it, mode / remark)

#: Slab track: Table 3 and the statements of Sec. 4.2-4.3.
TABLE3_SLAB_FREQUENCIES = (
    (183, "w1", "peak", "Table 3", "rail bouncing on the fastener stiffness"),
    (940, "w1", "peak", "Table 3", "first pinned-pinned mode"),
    (980, "psi2", "peak", "Table 3", "sliding-pinned-sliding* mode"),
    (2577, "det", "peak", "Table 3", "second pinned-pinned mode"),
    (2607, "w1", "peak", "Table 3", "sliding-sliding*-sliding mode"),
    (183, "psi2", "peak", "Sec. 4.2", "pitching frequency"),
    (183, "Q2", "dip", "Sec. 4.2", "pitching frequency"),
    (980, "Q2", "dip", "Sec. 4.2", "sliding-pinned-sliding*"),
    (183, "M1", "peak", "Sec. 4.2", "bouncing frequency"),
    (940, "M1", "peak", "Sec. 4.2", "first pinned-pinned"),
    (183, "det", "dip", "Sec. 4.2", "resonance of the semi-infinite track"),
    (2607, "det", "dip", "Sec. 4.2", "sliding-sliding*-sliding"),
    (183, "alpha11", "peak", "Sec. 4.3", "omega_n"),
    (183, "alpha12", "peak", "Sec. 4.3", "omega_n"),
    (183, "alpha22", "peak", "Sec. 4.3", "omega_n"),
    (940, "alpha11", "peak", "Sec. 4.3", "first pinned-pinned"),
    (940, "alpha22", "dip", "Sec. 4.3", "first pinned-pinned"),
    (2577, "alpha11", "dip", "Sec. 4.3", "second pinned-pinned"),
    (2577, "alpha22", "peak", "Sec. 4.3", "second pinned-pinned"),
)

#: Ballasted track: Table 6 and the statements of Sec. 5.1-5.2.
TABLE6_BALLASTED_FREQUENCIES = (
    (117, "w1", "peak", "Table 6", "rail and sleeper bouncing together on the ballast"),
    (243, "w1", "dip", "Table 6", "sleeper acting as a vibration absorber"),
    (531, "w1", "peak", "Table 6", "rail and sleeper bouncing out of phase"),
    (1077, "w1", "peak", "Table 6", "first pinned-pinned mode"),
    (1269, "psi2", "peak", "Table 6", "sliding-pinned-sliding* mode"),
    (2871, "w1", "dip", "Table 6", "second pinned-pinned mode"),
    (2955, "w1", "peak", "Table 6", "sliding*-sliding mode"),
    (117, "det", "dip", "Sec. 5.1", "resonance omega_n1 of the semi-infinite track"),
    (489, "det", "dip", "Sec. 5.1", "resonance omega_n2 of the semi-infinite track"),
    (2925, "det", "dip", "Sec. 5.1", "third resonance of the semi-infinite track"),
    (243, "det", "peak", "Sec. 5.1", "anti-resonance"),
    (2871, "det", "peak", "Sec. 5.1", "second pinned-pinned"),
    (117, "alpha11", "peak", "Sec. 5.2", "omega_n1"),
    (117, "alpha12", "peak", "Sec. 5.2", "omega_n1"),
    (117, "alpha22", "peak", "Sec. 5.2", "omega_n1"),
    (489, "alpha11", "peak", "Sec. 5.2", "omega_n2"),
    (489, "alpha12", "peak", "Sec. 5.2", "omega_n2"),
    (489, "alpha22", "peak", "Sec. 5.2", "omega_n2"),
    (243, "alpha11", "dip", "Sec. 5.2", "omega_anti"),
    (243, "alpha12", "dip", "Sec. 5.2", "omega_anti"),
    (243, "alpha22", "dip", "Sec. 5.2", "omega_anti"),
)

# ------------------------------------------------------------------------------------------
# The paper's fits (Sec. 4.4 and 5.2).

#: The frequency band (Hz) over which the paper fits and judges each layout's equivalent
#: system: 3-900 Hz for the slab track (Sec. 4.4, Table 4), 3-750 Hz for the ballasted track
#: (Sec. 5.2, Table 7).
FIT_BANDS: dict[str, tuple[float, float]] = {"slab": (3.0, 900.0), "ballasted": (3.0, 750.0)}

#: The pre-selected frequencies (Hz) of the paper's fits (Sec. 4.4 for Table 4, Sec. 5.2 for Table 7).
TABLE4_FIT_FREQUENCIES = (3.0, 15.0, 87.0, 117.0, 183.0, 207.0, 333.0, 597.0, 897.0)
TABLE7_FIT_FREQUENCIES = (3.0, 15.0, 27.0, 87.0, 117.0, 167.0, 217.0, 243.0, 277.0, 327.0, 377.0,
                          427.0, 457.0, 489.0, 517.0, 567.0, 617.0, 800.0)

#: Characteristic frequencies (Hz) the paper quotes for its constraints. For the second
#: repeated frequency of the ballasted cell the paper states 465 Hz (Sec. 5.2, with Eq. 24-27)
#: and reads 489 Hz off the receptance peak (Fig. 11); both are kept.
CONSTRAINT_FREQUENCIES = MappingProxyType({"f_n_slab": 183.0, "f_n1": 117.0, "f_n2_stated": 465.0,
                                           "f_n2_peak": 489.0, "f_anti": 243.0})

# ------------------------------------------------------------------------------------------
# The printed equivalent systems (Tables 4 and 7), N = 5 bars. Units: m (kg), J (kg m^2), L (m),
# k and s (N/m), c_l, c_r, d_l, d_r (N s/m), k_phi (N m/rad), c_phi (N m s/rad), mu (kg).
# Each entry of *_HALF_ULP is half a unit in the last printed digit of the row, i.e. the largest
# error that rounding to the printed value can introduce.

#: Table 4 (slab track) as printed: bars 2 and 4 are massless with zero end springs.
TABLE4 = MappingProxyType(dict(
    m=(10.080, 0.000, 67.013, 0.000, 257.134),
    J=(0.021, 0.000, 3.104, 0.000, 0.917),
    L=(0.091, 0.329, 0.430, 0.181, 0.119),
    k=(0.666e7, 0.0, 4.430e7, 0.0, 16.998e7),
    c_l=(0.0, 0.206e3, 2.876e3, 0.0, 0.0),
    c_r=(0.206e3, 2.876e3, 0.0, 0.0, 102.930e3),
    k_phi=(2.099e7, 1.275e7, 0.288e7, 0.061e7),
    c_phi=(0.321e3, 2.882e3, 0.529e3, 0.792e3),
))
TABLE4_HALF_ULP = MappingProxyType(dict(
    m=5e-4, J=5e-4, L=5e-4, k=5e-4 * 1e7, c_l=5e-4 * 1e3, c_r=5e-4 * 1e3, k_phi=5e-4 * 1e7,
    c_phi=5e-4 * 1e3,
))

#: Table 7 (ballasted track) as printed. The text extraction of the paper has its ``k_phi`` and
#: ``c_phi`` rows garbled; the values here are k_phi = (1.337, 0.650, 1.103, 0.347) x 1e7 N m/rad
#: and c_phi = (1373.233, 122.498, 3126.892, 16752.988) N m s/rad.
TABLE7 = MappingProxyType(dict(
    m=(7.546, 28.416, 29.702, 110.540, 246.240),
    J=(0.069, 1.146, 1.174, 13.360, 7.651),
    L=(0.191, 0.402, 0.398, 0.695, 0.353),
    k=(2.629e7, 9.899e7, 10.347e7, 38.508e7, 85.780e7),
    c_l=(0.000, 6.112, 102.754, 855.838, 9348.099),
    c_r=(4.760, 33275.108, 868.211, 3024.097, 37546.257),
    k_phi=(1.337e7, 0.650e7, 1.103e7, 0.347e7),
    c_phi=(1373.233, 122.498, 3126.892, 16752.988),
    mu=(15.913, 59.927, 62.640, 233.120, 519.301),
    s=(1.801e7, 4.071e7, 4.255e7, 15.836e7, 35.277e7),
    d_l=(18894.294, 10238.527, 12485.843, 14138.425, 2556.605),
    d_r=(4124.971, 10.122, 41742.950, 2555.712, 14094.973),
))
TABLE7_HALF_ULP = MappingProxyType(dict(
    m=5e-4, J=5e-4, L=5e-4, k=5e-4 * 1e7, c_l=5e-4, c_r=5e-4, k_phi=5e-4 * 1e7, c_phi=5e-4,
    mu=5e-4, s=5e-4 * 1e7, d_l=5e-4, d_r=5e-4,
))

#: Table 7's printed s_1 = 1.801e7 N/m with its second and third digits swapped (N/m): the value
#: that Eq. (23) and (30) give for bar 1, so very probably what the paper computed.
TABLE7_S1_TRANSPOSED = 1.081e7
