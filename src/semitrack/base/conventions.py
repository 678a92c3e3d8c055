"""Conventions shared by every layer: the receptance elements, their units and labels.

A 2x2 receptance is ordered ``[[a11, a12], [a21, a22]]`` = (w, psi) per (Q, M), w downward,
psi clockwise (the paper's sign convention). Reciprocity makes a12 = a21, so the distinct
elements are a11, a12 and a22. a12 = w/M is m/(N m) and a21 = psi/Q is rad/N: both are 1/N
(the radian is dimensionless), which is the one unit this package writes for them.
"""

from __future__ import annotations

__all__ = ["ELEMENTS", "ALL_ELEMENTS", "ELEMENT_UNITS", "ELEMENT_TEX", "EXACT_LABEL"]

#: How tables and figures call the exact (periodic-structure) result beside approximations.
EXACT_LABEL = "exact"

#: The three distinct elements of a reciprocal 2x2 receptance, with their (row, column) index.
ELEMENTS: dict[str, tuple[int, int]] = {"alpha11": (0, 0), "alpha12": (0, 1), "alpha22": (1, 1)}

#: All four elements, in row-major order (for files that write the full matrix).
ALL_ELEMENTS: dict[str, tuple[int, int]] = {"alpha11": (0, 0), "alpha12": (0, 1),
                                            "alpha21": (1, 0), "alpha22": (1, 1)}

#: SI units of each element (receptance: displacement or rotation per force or moment).
ELEMENT_UNITS: dict[str, str] = {"alpha11": "m/N", "alpha12": "1/N", "alpha21": "1/N",
                                 "alpha22": "rad/(N m)"}

#: Labels for figure axes (MathJax/matplotlib mathtext).
ELEMENT_TEX: dict[str, str] = {"alpha11": r"$\alpha_{11}$", "alpha12": r"$\alpha_{12}$",
                               "alpha21": r"$\alpha_{21}$", "alpha22": r"$\alpha_{22}$"}
