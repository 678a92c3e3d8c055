"""The wheel's defects and its radius in the contact: tread profiles, the centre's path, refusals.

The centre's path is checked against an independent computation of the issue's kind: the tread's
outline as a fine polygon, rolled vertex by vertex on the rail (a smooth rail) or set down at each
position (a perfect wheel over a dipped weld), and against the closed form of a new flat (arcs
about its edges).
"""

import math

import numpy as np
import pytest

import semitrack as st
from semitrack.model.centre_path import rail_drop, tread_rolling

R = 0.46
POLYGON_SPACING = 5e-5  # the reference's outline samples (m): its sag R (spacing / 2R)^2 / 2 is 7e-10 m


def rolled_polygon(wheel, x, u_from=-0.08, u_to=0.08):
    """The centre's drop of the wheel's outline as a polygon rolled on a line, pivot by pivot.

    The polygon's vertices sample the tread every POLYGON_SPACING over ``u_from..u_to`` (its corners
    included); the wheel starts resting on the vertex at ``u_from`` and turns clockwise about its
    pivot until the next vertex ahead touches the line, which becomes the pivot. The distance
    rolled is counted from the rotation 0 (the tread's origin straight below).
    """
    corners = np.concatenate([d._corners(R) for d in wheel.defects])
    u = np.union1d(np.arange(u_from, u_to, POLYGON_SPACING), corners)
    rho = R - wheel.tread_profile(u)
    beta = u / R
    pivots, theta_at = [], []  # (index, rotation when it becomes the pivot)
    i, theta = 0, beta[0]
    while i < u.size - 1:
        # at rotation theta the vertex j sits at angle beta_j - theta from straight down, ahead if > 0
        px, py = rho[i] * math.sin(beta[i] - theta), -rho[i] * math.cos(beta[i] - theta)
        qx = rho[i + 1:] * np.sin(beta[i + 1:] - theta) - px
        qy = -rho[i + 1:] * np.cos(beta[i + 1:] - theta) - py
        turn = np.arctan2(qy, qx)  # the angle of P->Q above the line: turning by it brings Q down onto it
        j = int(np.argmin(turn))
        pivots.append(i)
        theta_at.append(theta)
        theta, i = theta + float(turn[j]), i + 1 + j
    pivots.append(i)
    theta_at.append(theta)
    # the centre's horizontal place: it runs on circles about each pivot, which sit on the rail a
    # polygon edge apart; at rotation t about pivot p it is at xi_p - rho_p sin(beta_p - t)
    xi = np.zeros(len(pivots))
    for k in range(1, len(pivots)):
        a, b = pivots[k - 1], pivots[k]
        xi[k] = xi[k - 1] + math.hypot(rho[b] * math.sin(beta[b]) - rho[a] * math.sin(beta[a]),
                                       rho[b] * math.cos(beta[b]) - rho[a] * math.cos(beta[a]))
    # the origin: where the rotation is 0
    k0 = int(np.searchsorted(theta_at, 0.0, side="right") - 1)
    p0 = pivots[k0]
    origin = xi[k0] - rho[p0] * math.sin(beta[p0] - 0.0)
    xs = []
    for k in range(len(pivots) - 1):
        p = pivots[k]
        t = np.array([theta_at[k], theta_at[k + 1]])
        xs.append(xi[k] - rho[p] * np.sin(beta[p] - t) - origin)
    starts = np.array([s[0] for s in xs])
    k = np.clip(np.searchsorted(starts, x, side="right") - 1, 0, len(xs) - 1)
    piv = np.array(pivots[:-1])[k]
    centre = xi[k] - origin
    return R - np.sqrt(rho[piv] ** 2 - (x - centre) ** 2)


def set_down_polygon(rail, x, spacing=POLYGON_SPACING):
    """The centre's drop of a perfect wheel's polygon set down on ``rail`` at each x: its highest vertex contact."""
    psi = np.arange(-0.4, 0.4, spacing / R)
    out = np.empty(x.size)
    for k, xc in enumerate(x):
        out[k] = R - np.max(R * np.cos(psi) - rail(xc + R * np.sin(psi)))
    return out


class TestTreadProfile:
    def test_new_flat_is_a_chord_of_the_circle(self):
        flat = st.WheelFlat(0.05)
        wheel = st.Wheel(radius=R, defects=[flat])
        half = R * math.asin(0.025 / R)
        s = np.linspace(-half, half, 1001)
        rho = R - wheel.tread_profile(s)
        # every point of the flat lies on the line R cos(alpha) below the centre
        np.testing.assert_allclose(rho * np.cos(s / R), math.sqrt(R**2 - 0.025**2), rtol=0, atol=1e-15)
        assert flat.depth_on(R) == pytest.approx(R - math.sqrt(R**2 - 0.05**2 / 4), rel=1e-15)
        assert float(wheel.tread_profile(0.0)) == pytest.approx(flat.depth_on(R), rel=1e-14)
        assert np.all(wheel.tread_profile(np.array([-half - 1e-6, half + 1e-6, 1.0])) == 0)

    def test_rounded_flat_is_the_cosine_of_its_depth(self):
        wheel = st.Wheel(radius=R, defects=[st.WheelFlat(0.06, shape="rounded")])
        d = 0.06**2 / (16 * R)
        s = np.linspace(-0.03, 0.03, 601)
        np.testing.assert_allclose(wheel.tread_profile(s), 0.5 * d * (1 + np.cos(2 * np.pi * s / 0.06)),
                                   rtol=1e-12, atol=1e-20)
        assert st.WheelFlat(0.06, depth=1e-3, shape="rounded").depth_on(R) == 1e-3

    def test_profiles_are_periodic_and_placed(self):
        wheel = st.Wheel(radius=R, defects=[st.WheelFlat(0.04, position=1.0, shape="rounded"),
                                            st.WheelPolygon(order=12, amplitude=3e-5, phase=0.4)])
        s = np.linspace(0.0, 2.0, 77)
        np.testing.assert_allclose(wheel.tread_profile(s + wheel.circumference), wheel.tread_profile(s), atol=1e-15)
        polygon = 3e-5 * np.cos(12 * s / R - 0.4)
        np.testing.assert_allclose(wheel.tread_profile(s) - polygon,
                                   st.Wheel(defects=[wheel.defects[0]]).tread_profile(s), atol=1e-18)
        assert float(st.Wheel(defects=[wheel.defects[0]]).tread_profile(1.0)) == pytest.approx(0.04**2 / (16 * R))


class TestCentrePath:
    """wheel_centre_path against the polygon rolled (1e-7 m, the issue's figure)."""

    def test_new_flat_rides_the_arcs_about_its_edges(self):
        wheel = st.Wheel(radius=R, defects=[st.WheelFlat(0.05)])
        x = np.linspace(-0.04, 0.04, 4001)
        arcs = np.where(np.abs(x) < 0.025, R - np.sqrt(R**2 - (0.025 - np.abs(x)) ** 2), 0.0)
        path = st.wheel_centre_path(wheel, x)
        np.testing.assert_allclose(path, arcs, rtol=0, atol=1e-9)
        assert path.max() == pytest.approx(wheel.defects[0].depth_on(R), rel=1e-9)

    @pytest.mark.parametrize("defect", [st.WheelFlat(0.05), st.WheelFlat(0.06, shape="rounded"),
                                        st.WheelPolygon(order=20, amplitude=1e-4, phase=1.0)],
                             ids=["new-50mm", "rounded-60mm", "polygon-20"])
    def test_equals_the_polygon_rolled(self, defect):
        wheel = st.Wheel(radius=R, defects=[defect])
        x = np.linspace(-0.05, 0.05, 2001)
        reference = rolled_polygon(wheel, x)
        path = st.wheel_centre_path(wheel, x)
        assert np.abs(path - reference).max() < 1e-7
        assert np.ptp(reference) > 1e-4  # the defect is under the wheel: the comparison is not of zeros

    def test_rounded_flat_is_bridged(self):
        flat = st.WheelFlat(0.06, shape="rounded")
        wheel = st.Wheel(radius=R, defects=[flat])
        x = np.linspace(-0.04, 0.04, 8001)
        path = st.wheel_centre_path(wheel, x)
        profile = wheel.tread_profile(x)
        assert path.max() < 0.99 * flat.depth_on(R)  # the wheel does not reach the hollow's bottom
        assert np.all(path <= profile + 1e-12)  # and its centre never drops more than the profile
        np.testing.assert_allclose(path, path[::-1], atol=1e-10)

    def test_perfect_wheel_over_a_weld_equals_the_polygon_set_down(self):
        weld = st.DippedWeld(angle=0.01, length=0.4)
        x = np.linspace(-0.25, 0.25, 501)
        path = st.wheel_centre_path(st.Wheel(radius=R), x, profile=weld)
        reference = set_down_polygon(weld, x)
        assert np.abs(path - reference).max() < 1e-7
        assert path.max() < weld.depth  # it bridges the bottom
        # on the ramp the centre runs R (sqrt(1 + m^2) - 1) above the point contact's input
        ramp = np.abs(x + 0.1) < 0.02
        np.testing.assert_allclose(path[ramp], weld(x[ramp]) - R * (math.sqrt(1 + 0.005**2) - 1), atol=1e-12)

    def test_rail_profile_of_the_weld_gives_the_weld(self):
        weld = st.DippedWeld(angle=0.012, length=0.3, x=1.0)
        profile = st.RailProfile(np.array([0.85, 1.0, 1.15]), np.array([0.0, weld.depth, 0.0]))
        x = np.linspace(0.5, 1.5, 1001)
        np.testing.assert_allclose(rail_drop(profile, R, x), rail_drop(weld, R, x), atol=1e-15)
        bump = st.RailProfile(np.array([0.0, 0.01, 0.02]), np.array([0.0, -1e-4, 0.0]))  # a bump is met before
        assert float(rail_drop(bump, R, -5e-4)) < 0 == float(bump(-5e-4))

    def test_one_revolution_rolls_the_hull_perimeter(self):
        l = 0.08
        wheel = st.Wheel(radius=R, defects=[st.WheelFlat(l, position=0.7)])
        cut = 2 * (R * math.asin(l / (2 * R)) - l / 2)  # an arc replaced by its chord, twice over a flat
        assert tread_rolling(wheel).period == pytest.approx(2 * math.pi * R - cut, rel=0, abs=1e-9)
        x = np.linspace(0.5, 0.9, 401)
        np.testing.assert_allclose(st.wheel_centre_path(wheel, x + tread_rolling(wheel).period),
                                   st.wheel_centre_path(wheel, x), atol=1e-12)
        # the flat's centre comes below after the arc before it has rolled level: at 0.7 less half the cut
        x_c = 0.7 - cut / 2
        assert float(st.wheel_centre_path(wheel, x_c)) == pytest.approx(wheel.defects[0].depth_on(R), rel=1e-8)

    def test_polygonal_wheel_follows_its_profile_where_it_is_convex(self):
        wheel = st.Wheel(radius=R, defects=[st.WheelPolygon(order=10, amplitude=2e-5)])
        x = np.linspace(0.0, 1.0, 1001)
        path = st.wheel_centre_path(wheel, x)
        # a smooth convex outline: the support is its profile up to R p'^2 / 2 (the contact moves off
        # the centre's vertical), 4e-8 m here
        slope = 10 * 2e-5 / R
        assert np.abs(path - wheel.tread_profile(x)).max() < R * slope**2
        assert path.max() == pytest.approx(2e-5, rel=1e-3)

    def test_perfect_wheel_on_smooth_rail_does_not_move(self):
        assert np.all(st.wheel_centre_path(st.Wheel(), np.linspace(-5, 5, 11)) == 0)


class TestRefusals:
    @pytest.mark.parametrize("make", [
        lambda: st.Wheel(defects=[st.WheelFlat(3.0, shape="rounded")]),  # longer than the circumference
        lambda: st.Wheel(defects=[st.WheelFlat(0.95)]),  # a chord longer than the diameter
        lambda: st.WheelFlat(-0.05),
        lambda: st.WheelFlat(0.05, shape="square"),
        lambda: st.WheelFlat(float("nan")),
        lambda: st.Wheel(radius=0.0),
        lambda: st.Wheel(radius=float("nan")),
        lambda: st.Wheel(radius=-0.46),
        lambda: st.Wheel(defects=[st.WheelFlat(0.05, depth=1e-3)]),  # a new flat's depth is its chord's
        lambda: st.Wheel(defects=[st.WheelFlat(0.05, position=3.0)]),  # beyond the circumference
        lambda: st.Wheel(defects=st.WheelFlat(0.05)),  # one defect, not a sequence of them
        lambda: st.Wheel(defects=["flat"]),
        lambda: st.Wheel(contact="line"),
        lambda: st.WheelPolygon(order=0, amplitude=1e-5),
        lambda: st.WheelPolygon(order=2.5, amplitude=1e-5),
        lambda: st.WheelPolygon(order=4, amplitude=-1e-5),
        lambda: st.wheel_centre_path(st.Wheel(), [0.0], profile="weld"),
        lambda: st.wheel_centre_path("wheel", [0.0]),
    ])
    def test_bad_defects_are_refused(self, make):
        with pytest.raises(st.BadInput):
            make()

    def test_consistent_new_depth_is_accepted(self):
        depth = R - math.sqrt(R**2 - 0.05**2 / 4)
        assert st.Wheel(defects=[st.WheelFlat(0.05, depth=depth)]).defects[0].depth == depth

    def test_from_radii_sets_the_radius(self):
        assert st.Wheel.from_radii(wheel_radius=0.42).radius == 0.42
        with pytest.raises(st.BadInput, match="wheel_radius"):
            st.Wheel.from_radii(radius=0.42)
