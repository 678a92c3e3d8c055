"""Levenberg-Marquardt on the normal equations (the boundary refinement's solver).

Independent checks: it reaches the minimum MINPACK's lmder reaches (scipy's method="lm") on a
nonlinear fit and on an ill-scaled one, Rosenbrock's valley leads it to (1, 1), it is invariant
to the units of an unknown, and a spent budget is reported as such.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

from semitrack.boundary.levenberg import levenberg_marquardt


def _exponential_problem(scale=(1.0, 1.0, 1.0)):
    """y = a exp(-b t) + c sampled with noise; unknowns multiplied by ``scale``."""
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 4.0, 400)
    y = 2.5 * np.exp(-1.3 * t) + 0.4 + 0.01 * rng.standard_normal(t.size)
    s = np.asarray(scale)

    def fun(p):
        a, b, c = p / s
        return a * np.exp(-b * t) + c - y

    def jac(p):
        a, b, _ = p / s
        e = np.exp(-b * t)
        return np.stack([e, -a * t * e, np.ones_like(t)], axis=1) / s

    return fun, jac, np.array([1.0, 0.5, 0.0]) * s


def test_same_minimum_as_minpack():
    fun, jac, x0 = _exponential_problem()
    ours = levenberg_marquardt(fun, jac, x0)
    ref = least_squares(fun, x0, jac=jac, method="lm")
    assert ours.converged
    assert ours.cost == pytest.approx(ref.cost, rel=1e-10)
    np.testing.assert_allclose(ours.x, ref.x, rtol=1e-6)


def test_units_of_the_unknowns_do_not_matter():
    """Unknowns scaled by 1e-4 and 1e5 (Marquardt's scaling): the same fit in the original units."""
    scale = np.array([1e-4, 1.0, 1e5])
    fun, jac, x0 = _exponential_problem(scale)
    scaled = levenberg_marquardt(fun, jac, x0)
    plain = levenberg_marquardt(*_exponential_problem())
    np.testing.assert_allclose(scaled.x / scale, plain.x, rtol=1e-6)


def test_rosenbrock_valley():
    def fun(x):
        return np.array([10 * (x[1] - x[0] ** 2), 1 - x[0]])

    def jac(x):
        return np.array([[-20 * x[0], 10.0], [-1.0, 0.0]])

    result = levenberg_marquardt(fun, jac, np.array([-1.2, 1.0]))
    assert result.converged
    np.testing.assert_allclose(result.x, [1.0, 1.0], atol=1e-7)
    assert result.cost < 1e-20


def test_spent_budget_is_reported():
    fun, jac, x0 = _exponential_problem()
    result = levenberg_marquardt(fun, jac, x0, max_nfev=2)
    assert not result.converged and result.nfev == 2
    assert result.cost < 0.5 * float(fun(x0) @ fun(x0))  # the steps taken still went downhill


def test_boundary_refinement_matches_minpack():
    """On the refinement's own problem (36 poles, slab track): the cost MINPACK reaches."""
    import semitrack as st
    from semitrack.boundary.refinement import _AlphaProblem

    bnd = st.fit_boundary(st.slab_track(), band=(3.0, 3000.0), n_poles=24)
    f = np.geomspace(3.0, 3000.0, 300)
    alpha = st.semi_infinite_receptance(st.slab_track(), f)
    problem = _AlphaProblem(bnd.rational, f, alpha, np.ones((f.size, 3)))
    c0 = bnd.rational.coefficients.ravel() * 1.05  # off the minimum, as a vector fit leaves it
    ours = levenberg_marquardt(problem.fun, problem.jac, c0, max_nfev=40)
    ref = least_squares(problem.fun, c0, jac=problem.jac, method="lm", max_nfev=40)
    assert ours.cost <= ref.cost * (1 + 1e-6)
