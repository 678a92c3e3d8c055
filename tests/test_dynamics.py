"""The time-domain engine on its own: systems, state blocks, contacts of k wheels, both step loops.

Independent checks: closed forms (a two-mass chain's frequency through the scheme's frequency
map, a Maxwell element's receptance through the bilinear map), the contact equations solved by
SciPy, and the compiled loop against the NumPy reference loop to 1e-12 on every path (fixed and
moving loads and probes, state blocks, one and two wheels, loss of contact).
"""

import numpy as np
import pytest
import scipy.optimize
import scipy.sparse as sp
from timedomain_cases import boundary

import semitrack as st
from semitrack.dynamics.contact import HertzContacts, solve_hertz
from semitrack.dynamics.factor import factorise
from semitrack.dynamics.newmark import Newmark
from semitrack.dynamics.points import PointSet
from semitrack.dynamics.signals import sin2_ramp
from semitrack.dynamics.simulate import compiled_available, simulate
from semitrack.dynamics.states import StateBlock
from semitrack.dynamics.system import Connection, SecondOrderSystem, union

needs_numba = pytest.mark.skipif(not compiled_available(), reason="numba is not installed")


# ------------------------------------------------------------------------------------------------
# Systems and the scheme
# ------------------------------------------------------------------------------------------------
def test_a_union_of_two_masses_rings_at_its_warped_frequency():
    """Two 1 kg masses joined by a spring k: the relative motion rings at sqrt(2 k / m), which
    average acceleration maps to (2/dt) arctan(omega dt / 2); the centre of mass stays put."""
    mass = SecondOrderSystem([[1.0]], [[0.0]], [[0.0]])
    k = 4e4
    system = union({"a": mass, "b": mass}, [Connection(("a", 0), ("b", 0), k)])
    assert system.K.toarray().tolist() == [[k, -k], [-k, k]]
    omega = np.sqrt(2 * k)
    dt, n = 0.05 / omega, 4000
    res = simulate(system, Newmark(dt), n, record=None, u0=[0.5, -0.5])
    omega_bar = 2 / dt * np.arctan(omega * dt / 2)
    u = res["dofs"]
    np.testing.assert_allclose(u[:, 0] - u[:, 1], np.cos(omega_bar * res.t), atol=1e-10)  # measured 1.2e-11
    # the rigid mode has no stiffness: its round-off grows with t^2 (measured 2e-9 after 4000 steps)
    np.testing.assert_allclose(u.sum(axis=1), 0.0, atol=1e-8)


def test_a_connection_to_the_ground_and_the_block_names():
    one = SecondOrderSystem([[2.0]], [[0.0]], [[0.0]])
    two = union({"wheel": one, "bogie": one}, [Connection(("wheel", 0), None, 10.0, 3.0)])
    assert two.K.toarray().tolist() == [[10.0, 0.0], [0.0, 0.0]] and two.C[0, 0] == 3.0
    assert two.dofs("bogie").tolist() == [1]
    with pytest.raises(KeyError, match="no DOF block 'car'"):
        two.dofs("car")
    with pytest.raises(ValueError, match="connection DOF 3 of part 'wheel'"):
        union({"wheel": one}, [Connection(("wheel", 3), None, 1.0)])


def test_a_maxwell_state_block_is_its_receptance_at_the_warped_frequencies():
    """A mass on a spring k0 and, beside it, a spring k in series with a dashpot c (a Maxwell
    element, one state: its force x, dx/dt = -(k/c) x + k dy/dt): the DFT of the impulse
    response equals 1 / (m s^2 + k0 + k c s / (k + c s)) at s = i (2/dt) tan(omega dt/2)."""
    m, k0, k, c = 2.0, 2e4, 1e5, 50.0
    block = StateBlock([0], [[-k / c]], [[k]], [[1.0]], [[1.0]])
    system = SecondOrderSystem([[m]], [[0.0]], [[k0]], states=(block,))
    dt, n = 1e-4, 2**15
    g = np.zeros(n)
    g[1] = 1.0
    res = simulate(system, Newmark(dt), n - 1, loads=[(PointSet.on_dofs([0]), g)], record=None)
    u = res["dofs"][:, 0]
    assert np.abs(u[-50:]).max() < 1e-9 * np.abs(u).max()  # decayed: no wrap-around
    f = np.fft.rfftfreq(n, dt)[1:2000:97]
    s = 1j * np.tan(np.pi * f * dt) * 2 / dt
    ratio = (np.fft.rfft(u) / np.fft.rfft(g))[1:2000:97]
    np.testing.assert_allclose(ratio, 1 / (m * s**2 + k0 + k * c * s / (k + c * s)), rtol=1e-8)


def test_the_scheme_s_parameters_and_state_blocks():
    with pytest.raises(ValueError, match="gamma and beta"):
        Newmark(1e-3, beta=0.1)
    block = StateBlock([0], [[-1.0]], [[1.0]], [[1.0]], [[1.0]])
    system = SecondOrderSystem([[1.0]], [[0.0]], [[1.0]], states=(block,))
    with pytest.raises(ValueError, match="state blocks need the average-acceleration rule"):
        simulate(system, Newmark(1e-3, gamma=0.6, beta=0.3025), 10)
    with pytest.raises(ValueError, match="a state block on 1 DOFs with 1 states needs"):
        StateBlock([0], [[-1.0]], [[1.0, 2.0]], [[1.0]], [[1.0]])


# ------------------------------------------------------------------------------------------------
# The contact equations of k wheels
# ------------------------------------------------------------------------------------------------
def _complementarity(c_h, a, G, F):
    delta = a - G @ F
    return np.where(F > 0, F - c_h * np.maximum(delta, 0) ** 1.5, np.maximum(delta, 0))


@pytest.mark.parametrize("seed", range(5))
def test_contact_forces_of_several_wheels_solve_their_equations(seed):
    """Random SPD compliances with non-negative couplings (wheels on one rail), approaches from
    loose to tight: the forces are those SciPy finds, and satisfy F = c max(a - G F, 0)^1.5."""
    rng = np.random.default_rng(seed)
    k = 1 + seed % 4
    L = rng.uniform(0.0, 1.0, (k, k))
    G = 1e-9 * (L @ L.T + k * np.eye(k)) / k
    c_h = rng.uniform(5e10, 1e11, k)
    a = rng.uniform(-2e-5, 2e-4, k)
    F = np.zeros(k)
    iterations = solve_hertz(c_h, a, G, F, np.zeros((k, k + 5)))
    assert 0 <= iterations <= 30
    assert np.all(F >= 0)
    np.testing.assert_allclose(_complementarity(c_h, a, G, F), 0.0, atol=1e-9 * max(F.max(), 1.0))
    # SciPy from another start: the root is unique (a strictly convex problem's minimiser)
    sol = scipy.optimize.root(lambda f: f - c_h * np.maximum(a - G @ f, 0) ** 1.5, 0.5 * F + 10.0, method="hybr",
                              options={"xtol": 1e-14})
    np.testing.assert_allclose(F, sol.x, rtol=1e-8, atol=1e-3)


def test_a_wheel_off_the_rail_carries_nothing():
    F = np.zeros(2)
    G = np.array([[1e-9, 2e-10], [2e-10, 1e-9]])
    solve_hertz(np.array([9e10, 9e10]), np.array([1e-4, -1e-5]), G, F, np.zeros((2, 7)))
    assert F[1] == 0 and F[0] > 0
    assert solve_hertz(np.array([9e10]), np.array([-1.0]), np.array([[1e-9]]), F[:1], np.zeros((1, 6))) == 0
    assert F[0] == 0


# ------------------------------------------------------------------------------------------------
# The compiled loop against the NumPy loop, path by path
# ------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def slab_model():
    track = st.slab_track(damping="viscous")
    return st.TruncatedTrack(track, 3, "boundary", system=boundary("slab"), elements_per_bay=8)


def _both(system, stepper, n, **kwargs):
    return [simulate(system, stepper, n, compiled=c, **kwargs) for c in (False, True)]


def _assert_same(numpy_run, compiled_run, tol=1e-12):
    assert compiled_run.compiled and not numpy_run.compiled
    for name, ref in numpy_run.channels.items():
        if ref.size:
            err = np.max(np.abs(compiled_run[name] - ref)) / max(np.max(np.abs(ref)), 1e-300)
            assert err <= tol, (name, err)


@needs_numba
def test_compiled_loop_equals_numpy_loop_with_state_blocks_and_moving_points(slab_model):
    m = slab_model
    dt, n = 2e-5, 800
    t = dt * np.arange(n + 1)
    path = m.points(np.linspace(-1.5, 1.5, n + 1), moving=True)
    runs = _both(m.time_domain_system(), Newmark(dt), n,
                 loads=[(path, np.sin(300 * t)), (PointSet.on_dofs([m.dof(0.0)]), np.cos(2e3 * t))],
                 probes={"moving": path, "fixed": m.points([0.0, 0.3])}, record=[0, 5, 7])
    _assert_same(*runs)


def _wheels_on(model, xs, speed, n, dt, static=True, depth=6e-4):
    """k wheels (600 kg, no suspension, 100 kN each) at xs on ``model``, each its own phase of a
    corrugation of amplitude ``depth`` (6e-4 m: contact is lost and regained); from the static
    deflection, or dropped."""
    k = len(xs)
    parts = {"track": model.time_domain_system()}
    parts.update({f"wheel {i}": SecondOrderSystem([[600.0]], [[0.0]], [[0.0]]) for i in range(k)})
    system = union(parts)
    t = dt * np.arange(n + 1)
    paths = np.array(xs)[None, :] + speed * t[:, None]
    if speed > 0:
        points = PointSet.stacked(model.points(paths[:, i], moving=True) for i in range(k))
    else:
        points = model.points(xs)
    r = depth * np.sin(2 * np.pi * 400 * t[:, None] + np.arange(k)) * sin2_ramp(t - 0.002, 0.004)[:, None]
    wheels = np.concatenate([system.dofs(f"wheel {i}") for i in range(k)])
    contacts = HertzContacts(wheels, points, np.full(k, 9.3e10), r)
    u0 = None
    if static:
        N = points.matrix(model.n_dof, 0)
        u0 = np.zeros(system.n_dof)
        u0[:model.n_dof] = factorise(model.time_domain_system().K).solve(N.T @ np.full(k, 1e5))
        u0[wheels] = N @ u0[:model.n_dof] + (1e5 / 9.3e10) ** (2 / 3)
    return system, contacts, [(PointSet.on_dofs(wheels), np.full((n + 1, k), 1e5))], u0


@needs_numba
@pytest.mark.parametrize("xs, speed", [([0.0], 0.0), ([0.0, 1.2], 0.0), ([-1.0, 0.2], 60.0)])
@pytest.mark.parametrize("depth, tol", [(2e-5, 1e-12), (6e-4, 2e-11)], ids=["in contact", "losing contact"])
def test_compiled_loop_equals_numpy_loop_with_wheels(slab_model, xs, speed, depth, tol):
    """From the static deflection. In contact: 1e-12 (measured 1e-14 for one wheel, 5e-13 for a
    rolling pair). Each loss and regain of contact is an impact that amplifies the loops'
    different round-off (their summation orders and the compiled solve's reciprocal diagonal):
    3-6e-12 of the largest force (measured), held to 2e-11."""
    dt, n = 2e-5, 600
    system, contacts, loads, u0 = _wheels_on(slab_model, xs, speed, n, dt, depth=depth)
    runs = _both(system, Newmark(dt), n, loads=loads, contacts=contacts, u0=u0)
    assert np.any(runs[0]["contact force"] == 0) == (depth > 1e-4)
    _assert_same(*runs, tol=tol)


@needs_numba
def test_compiled_loop_equals_numpy_loop_for_wheels_dropped_on_the_rail(slab_model):
    """Dropped from rest onto the rail, two wheels bounce hard at first: the impacts amplify the
    loops' different round-off to 1e-10 of the largest force (measured 9e-11)."""
    dt, n = 2e-5, 600
    system, contacts, loads, _ = _wheels_on(slab_model, [-1.0, 0.2], 60.0, n, dt, static=False)
    _assert_same(*_both(system, Newmark(dt), n, loads=loads, contacts=contacts), tol=3e-10)


def test_simulate_refuses_what_it_cannot_run(slab_model):
    system = slab_model.time_domain_system()
    with pytest.raises(ValueError, match=r"loads\[0\] amplitudes must have shape \(11, 1\)"):
        simulate(system, Newmark(1e-5), 10, loads=[(PointSet.on_dofs([0]), np.zeros(5))])
    with pytest.raises(ValueError, match="record must hold DOF indices"):
        simulate(system, Newmark(1e-5), 10, record=[10**6])
    with pytest.raises(TypeError, match="system must be a SecondOrderSystem"):
        simulate("track", Newmark(1e-5), 10)
    skew = SecondOrderSystem(sp.eye(3), sp.csc_matrix((3, 3)), sp.diags([1.0, 2.0], [0, 1], shape=(3, 3)) + sp.eye(3))
    with pytest.raises(ValueError, match="compiled=True needs a real symmetric positive definite"):
        simulate(skew, Newmark(1e-3), 5, compiled=True)
    assert not simulate(skew, Newmark(1e-3), 5).compiled  # the NumPy loop takes any factor


def test_point_sets():
    p = PointSet(np.array([[[0, 1]], [[1, 2]]]), np.array([[[0.5, 0.5]], [[0.25, 0.75]]]))
    u = np.array([0.0, 2.0, 4.0])
    assert p.moving and p.values(u, 0).tolist() == [1.0] and p.values(u, 1).tolist() == [3.5]
    assert p.matrix(3, 1).toarray().tolist() == [[0.0, 0.25, 0.75]]
    with pytest.raises(ValueError, match="dofs must be non-negative"):
        PointSet([[[-1]]], [[[1.0]]])
    both = PointSet.stacked([PointSet.on_dofs([2]), PointSet(p.dofs[:1], p.weights[:1])])
    assert both.n_points == 2 and both.values(u).tolist() == [4.0, 1.0]
    with pytest.raises(ValueError, match="point sets stack only with the same rows"):
        PointSet.stacked([p, PointSet.on_dofs([0])])


@pytest.mark.parametrize("compiled", [False, pytest.param(True, marks=needs_numba)])
def test_motion_far_from_the_load_is_zero_not_subnormal(compiled):
    """An implicit step reaches every DOF with geometrically decaying amplitudes; far along a long
    track they would fall to subnormal numbers (a hundred times slower arithmetic) and stay:
    both loops set motion (u, v and a) below 1e-200 to zero, so none is ever subnormal."""
    model = st.TruncatedTrack(st.slab_track(damping="viscous"), 120, elements_per_bay=4)
    g = np.zeros(201)
    g[1] = 1e5
    res = simulate(model.time_domain_system(), Newmark(2e-5), 200, loads=[(PointSet.on_dofs([model.dof(0.0)]), g)],
                   record=None, compiled=compiled)
    u = np.abs(res["dofs"][-1])
    assert not np.any((u > 0) & (u < 1e-300)) and np.any(u == 0) and u.max() > 1e-9


@needs_numba
def test_compiled_loop_takes_a_contact_on_a_pinned_end_node():
    """At a pinned end node the rail's weights are all zero: the wheel then rests on nothing but
    its own DOF, and both loops must agree (the compiled contact solve once dropped it)."""
    model = st.TruncatedTrack(st.slab_track(damping="viscous"), 3, elements_per_bay=4)
    for x0, speed in ((model.x[0], 0.0), (model.x[-1] - 0.5, 50.0)):
        duration = 0.01
        runs = [st.wheel_rail_response(model, st.Wheel(), x=x0, speed=speed, dt=2e-5, duration=duration,
                                       ramp=0.005, compiled=c) for c in (False, True)]
        np.testing.assert_allclose(runs[1].force, runs[0].force, rtol=0, atol=1e-9 * np.abs(runs[0].force).max())
        np.testing.assert_allclose(runs[1].w_wheel, runs[0].w_wheel, rtol=0, atol=1e-11 * np.abs(runs[0].w_wheel).max())


@needs_numba
def test_a_wheel_coupled_to_the_track_runs_the_numpy_loop(slab_model):
    """The compiled contact solve needs each wheel apart from the track; a wheel tied to a rail DOF
    by a spring is run by the NumPy loop (compiled=None) or refused (compiled=True)."""
    dt, n = 2e-5, 100
    system, contacts, loads, u0 = _wheels_on(slab_model, [0.0], 0.0, n, dt)
    track = slab_model.time_domain_system()
    wheel = SecondOrderSystem([[600.0]], [[0.0]], [[0.0]])
    spring = Connection(("track", slab_model.dof(slab_model.x[5])), ("wheel 0", 0), 1e5)
    tied = union({"track": track, "wheel 0": wheel}, [spring])
    res = simulate(tied, Newmark(dt), n, loads=loads, contacts=contacts, u0=u0)
    assert not res.compiled
    with pytest.raises(ValueError, match="compiled=True needs each wheel apart from the track"):
        simulate(tied, Newmark(dt), n, loads=loads, contacts=contacts, u0=u0, compiled=True)
    assert simulate(system, Newmark(dt), n, loads=loads, contacts=contacts, u0=u0).compiled
