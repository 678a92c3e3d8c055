"""Moving Green's functions: the periodic FE track in time without truncation.

Independent checks, each against another method: the infinite FE track's receptances from its
Bloch waves against a long FE model with exact ends (frequency domain); the kernels against
Newmark run step by step on a long FE model (an impulse, and a standing load released); the
Python loops against the compiled one; whole runs (one wheel, two wheels, loss of contact, a
smooth rail's support-passing line) against the truncated FE model with broadband ends that holds
the path. The cache stores data that reads back equal, and refuses what is not its own.
"""

import json

import numpy as np
import pytest
import scipy.sparse.linalg as spl

import semitrack as st
from semitrack.fe.bloch import BlochCell
from semitrack.fe.kernelcache import cached_kernels, clear_kernel_memo
from semitrack.fe.kernels import grid_of, moving_kernels

SLAB = st.slab_track(damping="viscous")
BALLAST = st.ballasted_track(damping="viscous")
NE = 8  # coarse meshes: the checks are of the method, which holds for any mesh
SPEED, DT = 50.0, 1e-4


def _newmark_kernel(model, x_load, x_obs, n, dt, release=False):
    """w at the moving points ``x_obs[k]`` after a unit impulse at x_load at step 0 (or its standing load
    taken off after step 0), by Newmark's average acceleration on the FE model, step by step."""
    M, C, K = model.matrices()
    a0, a1 = 4 / dt**2, 2 / dt
    lu = spl.splu((K + a1 * C + a0 * M).tocsc())
    b = model.output_matrix([x_load]).toarray()[0]
    u = spl.splu(K.tocsc()).solve(b) if release else np.zeros(model.n_dof)
    v, a = np.zeros_like(u), np.zeros_like(u)
    obs = model.output_matrix(x_obs).toarray()
    out = [obs[0] @ u] if release else []
    for k in range(1 if release else 0, n):
        un = lu.solve(M @ (a0 * u + 4 / dt * v + a) + C @ (a1 * u + v) + (b if k == 0 and not release else 0))
        an = a0 * (un - u) - 4 / dt * v - a
        v, a, u = v + dt / 2 * (a + an), an, un
        out.append(obs[k] @ u)
    return np.array(out)


def test_the_bloch_waves_give_the_long_fe_track():
    """The infinite FE track from one cell against a 40-bay FE model with exact ends: within 1e-9 below 300 Hz."""
    grid = np.array([0.0, 0.1, 0.3])
    cell = BlochCell(BALLAST, NE, grid)
    f = np.array([20.0, 90.0, 280.0])
    w = cell.waves(2j * np.pi * f)
    model = st.TruncatedTrack(BALLAST, 20, "exact", elements_per_bay=NE)
    out = lambda x: model.output_matrix([x]).toarray().T  # noqa: E731
    U = model.solve(f, out(0.1))[:, :, 0]
    near = cell.observe(w.field)[:, :, 1]
    for q, x in enumerate(grid):
        assert np.allclose(near[:, q], U @ out(x)[:, 0], rtol=1e-9, atol=0)
    d = BALLAST.spacing
    right = np.einsum("fqa,fab,fb->fq", w.shows_right, np.linalg.matrix_power(w.step_right, 2), w.out_right[:, :, 1])
    left = np.einsum("fqa,fa->fq", w.shows_left, w.out_left[:, :, 1])
    for q, x in enumerate(grid):
        assert np.allclose(right[:, q], U @ out(3 * d + x)[:, 0], rtol=1e-8, atol=0)
        assert np.allclose(left[:, q], U @ out(-d + x)[:, 0], rtol=1e-8, atol=0)


@pytest.fixture(scope="module")
def slab_kernels():
    grid = grid_of(SLAB, SPEED, DT, (0.0, -0.5))
    return grid, moving_kernels(SLAB, NE, grid, 1500, start=3)


def test_the_kernels_are_newmark_on_the_infinite_fe_track(slab_kernels):
    """Impulse and release kernels, self and cross, against Newmark step by step on a 40-bay pinned model
    (no reflection returns within 200 steps): within 1e-6 of their peak."""
    grid, kernels = slab_kernels
    h, n = grid.step, 200
    model = st.TruncatedTrack(SLAB, 40, "pinned", elements_per_bay=NE)
    for p in (0, 3, grid.positions - 1):
        for lag in grid.lags:
            x_obs = (p + lag + np.arange(n)) * h
            ref = _newmark_kernel(model, p * h, x_obs, n, DT)
            ker = kernels.impulse[lag][p, :n]
            assert np.abs(ker - ref).max() <= 1e-6 * np.abs(kernels.impulse[0]).max()
    for lag, p0 in kernels.release:
        ref = _newmark_kernel(model, p0 * h, (p0 + lag + np.arange(n)) * h, n, DT, release=True)
        assert np.abs(kernels.release[lag, p0][:n] - ref).max() <= 1e-6 * np.abs(ref).max()


def test_a_memory_shorter_than_a_spacing_sums_only_the_loads_that_reach_it():
    """A bogie whose memory (40 steps) is far shorter than a support spacing (325 steps): the set-up
    sums only the loads within the memory of each point, and every kernel value equals the plain sum over
    frequencies of the cell's receptance, evaluated here point by point in cells 0 and +-1."""
    from semitrack.fe.bloch import warped_s
    from semitrack.fe.kernels import ALIAS_FACTOR, _frequencies

    dt, L = 1e-4, 40
    grid = grid_of(SLAB, 20.0, dt, st.Bogie().offsets)
    kernels = moving_kernels(SLAB, NE, grid, L)
    P = grid.positions
    n_fft = 2 * ALIAS_FACTOR * (L // 2)
    omega = _frequencies(n_fft, dt)
    cell = BlochCell(SLAB, NE, grid.step * np.arange(P))
    w = cell.waves(warped_s(omega, dt))
    near = cell.observe(w.field)  # (n_f, q, p)

    def plain(p, lag, k):
        j, q = divmod(p + lag + k, P)
        if j == 0:
            G = near[:, q, p]
        else:
            shows, step, out = ((w.shows_right, w.step_right, w.out_right) if j > 0 else
                                (w.shows_left, w.step_left, w.out_left))
            G = np.array([shows[f, q] @ np.linalg.matrix_power(step[f], abs(j) - 1) @ out[f, :, p]
                          for f in range(omega.size)])
        return float(np.real(np.sum(2.0 / n_fft * G * np.exp(1j * omega * dt * k))))

    peak = np.abs(kernels.impulse[0]).max()
    checked = 0
    for lag in grid.lags:
        for p in (0, 7, P // 2, P - 3, P - 1):
            for k in (0, 1, 17, L - 1):
                assert abs(kernels.impulse[lag][p, k] - plain(p, lag, k)) <= 1e-12 * peak, (lag, p, k)
                checked += 1
    assert checked == 3 * 5 * 4 and P > 8 * L and len(grid.lags) == 3


def test_the_grid_rounds_the_speed_and_the_offsets():
    grid = grid_of(BALLAST, 300 / 3.6, 2e-5, (0.0, -2.5))
    assert grid.positions == 360 and grid.offsets == (0, -1500)
    assert abs(grid.speed - 300 / 3.6) / (300 / 3.6) <= 1 / (2 * grid.positions)
    odd = grid_of(BALLAST, 84.0, 2e-5, (0.0, -2.501))
    assert odd.positions == round(0.6 / (84.0 * 2e-5)) and odd.speed == 0.6 / (odd.positions * 2e-5)
    assert odd.lags == (odd.offsets[1], 0, -odd.offsets[1])
    with pytest.raises(ValueError, match="at least 4 steps"):
        grid_of(BALLAST, 300.0, 1e-3)


def _rough(speed, period=0.05):
    lam = st.third_octave_bands(0.04, 0.5)[0]
    return st.roughness_from_spectrum(speed, lam, np.full(lam.size, 0.0), period=period, seed=2)


@pytest.fixture(scope="module")
def boundary():
    return st.fit_boundary(SLAB)


def _truncated(res, boundary, duration, rough="broadband", profile=None):
    """The same run on the truncated FE model with broadband ends that holds its path, 40 bays to spare
    (20 leave 1e-3 of reflections on this coarse mesh)."""
    reach = np.abs(res.x).max() + SLAB.spacing
    model = st.TruncatedTrack(SLAB, int(np.ceil(reach / SLAB.spacing)) + 40, "boundary", system=boundary,
                              elements_per_bay=NE)
    x0 = res.x[0] if res.x.ndim == 1 else res.x[0, 0]
    return st.wheel_rail_response(model, res.vehicle, _rough(res.speed) if rough == "broadband" else rough,
                                  x=float(x0), speed=res.speed, dt=res.dt, duration=duration, profile=profile)


def test_one_wheel_and_two_agree_with_the_truncated_model(boundary):
    """A rough rail at 50 m/s: the force's fluctuation within 1e-3 rms of the truncated model's
    (measured 3e-4 on this coarse mesh: the truncated model's own reflections, 3e-6 with 120 bays to spare),
    for one wheel and for two 0.5 m apart."""
    for vehicle in (st.Wheel(), st.WheelGroup((st.Wheel(), st.Wheel()), spacing=(0.0, -0.5))):
        res = st.moving_green_response(SLAB, vehicle, _rough(SPEED), x=-1.0, speed=SPEED, dt=DT,
                                       duration=0.1, memory=0.15, elements_per_bay=NE)
        ref = _truncated(res, boundary, 0.1)
        F, Fr = res.force.reshape(res.t.size, -1), ref.force.reshape(ref.t.size, -1)
        for i in range(F.shape[1]):
            fluct = Fr[:, i] - Fr[:, i].mean()
            assert np.sqrt(np.mean((F[:, i] - Fr[:, i]) ** 2)) <= 1e-3 * np.sqrt(np.mean(fluct**2))


def test_loss_of_contact_as_in_the_truncated_model(boundary):
    """A 0.2 mm corrugation of 0.1 m at 50 m/s: the wheel leaves the rail in both, at the same steps."""
    rough = st.corrugation(speed=grid_of(SLAB, SPEED, DT).speed, wavelength=0.1, amplitude=2e-4)
    res = st.moving_green_response(SLAB, st.Wheel(), rough, x=-1.0, speed=SPEED, dt=DT, duration=0.1,
                                   memory=0.15, elements_per_bay=NE)
    ref = _truncated(res, boundary, 0.1, rough)
    assert res.lost_contact and ref.lost_contact
    assert np.count_nonzero(res.in_contact != ref.in_contact) <= 2
    assert np.abs(res.force - ref.force).max() <= 1e-3 * ref.force.max()


def test_a_dipped_weld_as_in_the_truncated_model(boundary):
    """A profile fixed on the rail (a dipped weld) is the rail's shape, not the track's: both routes meet it alike,
    the P1 peak within 1e-3."""
    weld = st.DippedWeld(angle=0.01, length=0.4, x=0.5)
    res = st.moving_green_response(SLAB, st.Wheel(), None, x=-1.0, speed=SPEED, dt=DT, duration=0.06,
                                   memory=0.15, elements_per_bay=NE, profile=weld)
    ref = _truncated(res, boundary, 0.06, None, weld)
    assert res.force.max() > 1.2 * st.Wheel().preload
    assert np.abs(res.force - ref.force).max() <= 1e-3 * (ref.force.max() - ref.force.min())


def test_a_wheel_flat_as_in_the_truncated_model(boundary):
    """A wheel's own defect comes round as it rolls: a new 50 mm flat, met twice at 50 m/s, gives the truncated
    model's force within 1e-3 of its range on both routes' shared input (the centre's path)."""
    wheel = st.Wheel(defects=[st.WheelFlat(0.05, position=0.5)])
    res = st.moving_green_response(SLAB, wheel, None, x=-1.0, speed=SPEED, dt=DT, duration=0.07, memory=0.15,
                                   elements_per_bay=NE)
    ref = _truncated(res, boundary, 0.07, None)
    assert np.count_nonzero(np.diff((res.force > 1.5 * wheel.preload).astype(int)) == 1) >= 2  # two impacts
    assert np.abs(res.force - ref.force).max() <= 1e-3 * (ref.force.max() - ref.force.min())


def test_a_smooth_rail_shows_the_support_passing_line(boundary):
    """No roughness: the force's line at speed / spacing (tens of N) is the truncated model's within 1e-3,
    and so is the whole spectrum (the wheel's bounce set off by the start among it)."""
    res = st.moving_green_response(SLAB, st.Wheel(), None, x=-1.0, speed=SPEED, dt=DT, duration=0.2,
                                   memory=0.15, elements_per_bay=NE)
    ref = _truncated(res, boundary, 0.2, None)
    f, amp = res.force_spectrum(after=0.05)
    _, amp_ref = ref.force_spectrum(after=0.05)
    line = np.argmin(np.abs(f - res.speed / SLAB.spacing))
    assert amp[line] > 10.0 and amp[line] > 5 * np.median(amp[1:])  # the line stands out (N)
    assert abs(amp[line] - amp_ref[line]) <= 1e-3 * amp_ref[line]
    assert np.abs(amp - amp_ref).max() <= 1e-3 * amp_ref.max()


def test_the_python_loops_are_the_compiled_one(slab_kernels):
    """The general Python loop, the one-wheel loop in floats and the compiled loop give the same run."""
    pytest.importorskip("numba")
    rough = _rough(SPEED)
    one = [st.moving_green_response(SLAB, st.Wheel(), rough, x=-1.0, speed=SPEED, dt=DT, duration=0.03,
                                    memory=0.15, elements_per_bay=NE, compiled=c) for c in (False, True)]
    assert np.allclose(one[0].force, one[1].force, rtol=1e-12, atol=1e-9)
    grid, kernels = slab_kernels
    group = st.WheelGroup((st.Wheel(), st.Wheel()), spacing=(0.0, -0.5))
    two = [st.moving_green_response(SLAB, group, rough, x=3 * grid.step, speed=SPEED, dt=DT, duration=0.03,
                                    kernels=kernels, compiled=c) for c in (False, True)]
    assert np.allclose(two[0].force, two[1].force, rtol=1e-12, atol=1e-9)


def test_the_cache_reads_back_what_it_wrote_and_refuses_the_rest(tmp_path):
    grid = grid_of(SLAB, SPEED, DT)
    clear_kernel_memo()
    first = cached_kernels(SLAB, NE, None, grid, 300, None, tmp_path)
    files = list(tmp_path.glob("kernels-*.npz"))
    assert len(files) == 1
    clear_kernel_memo()
    again = cached_kernels(SLAB, NE, None, grid, 300, None, tmp_path)
    assert again.elapsed == first.elapsed  # read, not computed
    assert np.array_equal(again.impulse[0], first.impulse[0]) and again.release.keys() == first.release.keys()
    with np.load(files[0], allow_pickle=False) as data:
        assert json.loads(str(data["key"]))["mesh"] == ["elements", NE]
    files[0].write_bytes(b"\x80\x04not an npz")  # a pickle's opening bytes: never unpickled, computed again
    clear_kernel_memo()
    redone = cached_kernels(SLAB, NE, None, grid, 300, None, tmp_path)
    assert np.array_equal(redone.impulse[0], first.impulse[0])
    other = cached_kernels(SLAB, NE, None, grid, 320, None, tmp_path)  # another memory: another file
    assert other.memory == 320 and len(list(tmp_path.glob("kernels-*.npz"))) == 2


def test_what_the_route_does_not_hold_is_refused(slab_kernels):
    _, kernels = slab_kernels
    slab = st.example_track("floating-slab")
    with pytest.raises(ValueError, match="flexible slab"):
        st.moving_green_response(slab, st.Wheel(), speed=SPEED, dt=DT, duration=0.03)
    with pytest.raises(ValueError, match="phase"):  # the kernels' release is for another start
        st.moving_green_response(SLAB, st.WheelGroup((st.Wheel(), st.Wheel()), spacing=(0.0, -0.5)), speed=SPEED,
                                 dt=DT, duration=0.03, x=0.0, kernels=kernels)
    with pytest.raises(ValueError, match="steps per spacing"):
        st.moving_green_response(SLAB, st.Wheel(), speed=SPEED, dt=2 * DT, duration=0.03, kernels=kernels)
    with pytest.raises(ValueError, match="another track"):
        st.moving_green_response(SLAB.replace(kv=2 * SLAB.kv), st.WheelGroup((st.Wheel(), st.Wheel()),
                                                                             spacing=(0.0, -0.5)),
                                 speed=SPEED, dt=DT, duration=0.03, x=3 * kernels.grid.step, kernels=kernels)


def test_work_beyond_reason_is_refused_before_it_starts(tmp_path):
    """A memory of 100 s or a run of an hour is refused at once, naming what to change; a cache file
    holding an object array (a pickle inside an npz) is never unpickled but computed again."""
    import time

    start = time.perf_counter()
    with pytest.raises(ValueError, match="shorter memory"):
        st.moving_green_kernels(BALLAST, 300 / 3.6, 2e-5, memory=100.0)
    grid = grid_of(SLAB, SPEED, DT)
    kernels = moving_kernels(SLAB, NE, grid, 300)
    with pytest.raises(ValueError, match="simulate less"):
        st.moving_green_response(SLAB, st.Wheel(), speed=SPEED, dt=DT, duration=3600.0, kernels=kernels)
    assert time.perf_counter() - start < 5.0
    clear_kernel_memo()
    first = cached_kernels(SLAB, NE, None, grid, 300, None, tmp_path)
    (path,) = tmp_path.glob("kernels-*.npz")
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    arrays["key"] = np.array([{"not": "data"}], dtype=object)
    np.savez(path, **arrays, allow_pickle=True)
    clear_kernel_memo()
    again = cached_kernels(SLAB, NE, None, grid, 300, None, tmp_path)
    assert again.elapsed != first.elapsed and np.array_equal(again.impulse[0], first.impulse[0])


def test_kernels_are_used_only_where_they_hold(slab_kernels):
    """Kernels of another mesh, damping or memory, a roughness at another speed and nonsense speeds or starts are
    refused; another preload and a vehicle whose first wheel is not at its origin use them."""
    grid, kernels = slab_kernels
    group = st.WheelGroup((st.Wheel(), st.Wheel()), spacing=(0.0, -0.5))
    run = {"speed": SPEED, "dt": DT, "duration": 0.03, "x": 3 * grid.step, "kernels": kernels}
    for wrong in ({"elements_per_bay": 16}, {"f_ref": 10.0}, {"memory": 0.3}):
        with pytest.raises(ValueError, match="other settings"):
            st.moving_green_response(SLAB, group, **run, **wrong)
    with pytest.raises(ValueError, match="roughness.speed"):
        st.moving_green_response(SLAB, group, _rough(80.0), **run)
    for bad in ({"speed": 0.0}, {"speed": float("nan")}, {"x": float("inf")}):
        with pytest.raises(ValueError):
            st.moving_green_response(SLAB, group, **{**run, **bad})
    heavy = st.WheelGroup((st.Wheel(preload=1.5e5), st.Wheel()), spacing=(0.0, -0.5))
    assert st.moving_green_response(SLAB, heavy, **run).force[-1, 0] > 1.4e5
    shifted = st.WheelGroup((st.Wheel(), st.Wheel()), spacing=(0.1, -0.4))
    own = st.moving_green_kernels(SLAB, SPEED, DT, shifted.offsets, x=0.0, memory=0.15, elements_per_bay=NE)
    res = st.moving_green_response(SLAB, shifted, speed=SPEED, dt=DT, duration=0.03, kernels=own)
    assert np.allclose(res.x[0], [0.1, -0.4], atol=grid.step)


@pytest.mark.parametrize("spoil", ["lags", "starts", "flexibility"])
def test_a_cache_file_with_foreign_arrays_is_computed_again(tmp_path, spoil):
    grid = grid_of(SLAB, SPEED, DT)
    clear_kernel_memo()
    first = cached_kernels(SLAB, NE, None, grid, 300, None, tmp_path)
    (path,) = tmp_path.glob("kernels-*.npz")
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    arrays[spoil] = {"lags": np.array(0), "starts": arrays["starts"] + 1,
                     "flexibility": arrays["flexibility"] + 0j}[spoil]
    np.savez(path, **arrays)
    clear_kernel_memo()
    again = cached_kernels(SLAB, NE, None, grid, 300, None, tmp_path)
    assert again.elapsed != first.elapsed and np.array_equal(again.impulse[0], first.impulse[0])


def test_the_kernels_are_stored_in_the_loops_order(slab_kernels):
    """``loop`` is what the step loop reads (row q: a loading wheel at phase q now, its forces m steps ago at
    phase q - m); ``impulse`` reads it back by phase, and the cache stores the loop's order as it is."""
    from semitrack.fe.kernels import loop_order

    grid, kernels = slab_kernels
    assert kernels.loop.shape == (len(grid.lags), grid.positions, kernels.memory) and kernels.loop.flags.c_contiguous
    P = grid.positions
    for r, lag in enumerate(grid.lags):
        h = kernels.impulse[lag]
        for q, m in [(0, 0), (3, 5), (P - 1, P + 2), (1, kernels.memory - 1)]:
            assert kernels.loop[r, q, m] == h[(q - m) % P, m]
        assert np.array_equal(loop_order(h), kernels.loop[r])
        assert np.shares_memory(kernels.rows(lag), kernels.loop)


def test_a_second_run_spends_its_time_in_the_loop(slab_kernels):
    """With the kernels at hand a run re-arranges nothing and samples the roughness once: at least 80 % of its wall
    time is the step loop (the best of three, a loaded machine slowing both alike)."""
    pytest.importorskip("numba")
    import time

    grid, kernels = slab_kernels
    group = st.WheelGroup((st.Wheel(), st.Wheel()), spacing=(0.0, -0.5))
    run = {"x": 3 * grid.step, "speed": SPEED, "dt": DT, "kernels": kernels}
    rough = _rough(SPEED)
    st.moving_green_response(SLAB, group, rough, duration=0.03, **run)  # compiled and warm
    shares = []
    for _ in range(3):
        start = time.perf_counter()
        res = st.moving_green_response(SLAB, group, rough, duration=0.5, **run)
        shares.append(res.elapsed / (time.perf_counter() - start))
    assert max(shares) >= 0.8, shares


def test_the_roughness_on_a_grid_is_its_sum_of_cosines():
    """The block product of a period of no whole steps, and one sampling shared by wheels whole steps apart,
    against the cosines sample by sample."""
    from semitrack.interaction.excitation import rail_input

    rough = _rough(SPEED).at_speed(SPEED * 1.0123)
    dt, n = 7.3e-5, 4001
    t = dt * np.arange(n)
    assert rough.period / dt != round(rough.period / dt)
    assert np.abs(rough.sampled(dt, n) - rough(t)).max() <= 1e-11 * np.abs(rough(t)).max()
    h = rough.speed * dt
    x = np.arange(n)[:, None] * h + np.array([0.0, -37 * h, 12 * h, 0.3 * h])[None, :]  # the last one off the grid
    r = rail_input(rough, x, dt, 1e-9)  # no fade after step 0: a ramp of 1e-9 s
    for i in range(x.shape[1]):
        ref = rough(t + (x[0, i] - x[0, 0]) / rough.speed)
        assert np.abs(r[1:, i] - ref[1:]).max() <= 1e-11 * np.abs(ref).max()


def test_a_short_memory_is_warned_of_where_the_kernels_are_made(tmp_path):
    """moving_green_kernels itself warns (naming the aliasing too), at its caller's line; a run that computes its
    kernels warns once; a memory long enough does not warn."""
    import warnings

    clear_kernel_memo()
    with pytest.warns(RuntimeWarning, match=r"aliasing\); give a longer memory") as caught:
        short = st.moving_green_kernels(SLAB, SPEED, DT, memory=0.01, elements_per_bay=NE)
    assert short.tail > 1e-3 and caught[0].filename == __file__
    with pytest.warns(RuntimeWarning, match="give a longer memory") as caught:
        st.moving_green_response(SLAB, st.Wheel(), speed=SPEED, dt=DT, duration=0.03, memory=0.01,
                                 elements_per_bay=NE)
    assert len([w for w in caught if "memory" in str(w.message)]) == 1 and caught[0].filename == __file__
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert st.moving_green_kernels(SLAB, SPEED, DT, memory=0.15, elements_per_bay=NE).tail < 1e-3


def test_the_set_up_s_parts_give_the_same_kernels_on_any_number_of_cores(monkeypatch):
    """The frequency blocks are summed in parts (on threads where there are cores): the parts follow from
    the problem alone, so one core and two give the same numbers bit for bit, and the one-part sum to
    round-off."""
    from semitrack.base import parallel
    from semitrack.fe import kernels as kernel_module
    grid = grid_of(SLAB, SPEED, DT, (0.0, -0.5))
    runs = {}
    for parts, cores in ((2, 1), (2, 2), (1, 1)):
        monkeypatch.setattr(kernel_module, "PARTIAL_SUMS", parts)
        monkeypatch.setattr(parallel, "available_cores", lambda cores=cores: cores)
        runs[parts, cores] = moving_kernels(SLAB, NE, grid, 600)
    assert np.array_equal(runs[2, 1].loop, runs[2, 2].loop)
    assert all(np.array_equal(runs[2, 1].release[k], runs[2, 2].release[k]) for k in runs[2, 1].release)
    peak = np.abs(runs[1, 1].loop).max()
    assert 0 < np.abs(runs[2, 2].loop - runs[1, 1].loop).max() <= 1e-14 * peak  # summed otherwise, not copied


def test_the_phased_point_field_is_the_cell_s_field_with_the_load_s_phase(monkeypatch):
    """Cell 0's field of a load at each grid point, DOF first and with the load's phase, compiled and in NumPy,
    is the cell's own field (its loaded DOFs' field through the shape weights) to round-off; and the kernels
    made without numba are those made with it."""
    import sys

    from semitrack.fe.bloch import warped_s
    from semitrack.fe.pointfield import phased_point_field, phased_point_field_numpy

    grid = grid_of(SLAB, SPEED, DT, (0.0, -0.5))
    P = grid.positions
    cell = BlochCell(SLAB, NE, grid.step * np.arange(P))
    omega = 2 * np.pi * np.array([35.0, 410.0, 2900.0])
    w = cell.waves(warped_s(omega, DT))
    phase = np.exp(-1j * DT * omega[:, None] * np.arange(P)[None, :])
    expected = (w.field * phase[:, None, :]).transpose(1, 0, 2)
    scale = np.abs(expected).max()
    for made in (phased_point_field, phased_point_field_numpy):
        got = made(w.loaded, cell.grid_loaded, cell.grid_weights, phase)
        assert got.shape == (cell.model.n_dof, omega.size, P) and got.flags.c_contiguous
        assert np.abs(got - expected).max() <= 1e-14 * scale
    with_numba = moving_kernels(SLAB, NE, grid, 300)
    monkeypatch.setitem(sys.modules, "semitrack.fe.compiled", None)  # importing it now raises ImportError
    without = moving_kernels(SLAB, NE, grid, 300)
    peak = np.abs(with_numba.loop).max()
    assert np.abs(without.loop - with_numba.loop).max() <= 1e-14 * peak
    assert all(np.abs(without.release[k] - with_numba.release[k]).max() <= 1e-14 * peak for k in without.release)
