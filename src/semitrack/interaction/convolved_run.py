"""The run shared by the routes whose rail is a convolution: the static start and the step loop.

The rail under the wheels is known by its impulse responses (the exact infinite track's, or the
periodic FE track's moving Green's functions), the vehicle by its matrices. Both routes hand
:func:`convolved_run` the loop's kernels, pairs, releases, phases and local flexibility
(:func:`semitrack.dynamics.convolved.convolved_steps` says what each is); it starts the vehicle
at rest in the static equilibrium under the preloads, the rail deflected by the standing
preloads ``w_0 = e[0] P0 + flexibility P0`` (a wheel standing on its flat is ``r[0]`` lower), and
runs the loop, compiled or in Python.
"""

from __future__ import annotations

import time

import numpy as np

from ..dynamics.newmark import Newmark
from ..dynamics.simulate import convolved_loop
from ..fe.kerneltail import KernelTail
from ..model.vehicle import Vehicle, vehicle_step

__all__ = ["convolved_run"]


def convolved_run(vehicle: Vehicle, kernels: np.ndarray, pair: np.ndarray, release: np.ndarray, phase0: np.ndarray,
                  flexibility: np.ndarray, r: np.ndarray, dt: float, compiled: bool | None,
                  tail: KernelTail | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The static start and the step loop of a vehicle against a convolution.

    With a ``tail``, ``kernels`` are its heads: the loop runs in blocks of the tail's start, and before
    each block the tail's share of the rail under the wheels, from forces older than the block, is
    added to the wheels' input (and after it to the rail's displacement).

    Parameters
    ----------
    vehicle : Vehicle
        The vehicle, its k wheels first.
    kernels : ndarray, shape (n_kernels, P, L)
        The kernels as the loop reads them (m/N).
    pair : ndarray of int64, shape (k, k)
        Which kernel gives w at wheel i per force at wheel j.
    release : ndarray, shape (k, k, R)
        The release of the standing preloads (m/N); ``release[:, :, 0]`` is the static receptance.
    phase0 : ndarray of int64, shape (k,)
        Each wheel's phase at the start.
    flexibility : ndarray, shape (P,)
        Local compliance in series with a contact at each phase (m/N).
    r : ndarray, shape (n_steps + 1, k)
        Each wheel's input (m, :func:`semitrack.interaction.excitation.rail_input`).
    dt : float
        Time step (s).
    compiled : bool or None
        The loop compiled (True), in Python (False) or compiled where numba is installed (None).
    tail : KernelTail, optional
        The kernels' tails in low rank (:mod:`semitrack.fe.kerneltail`); None: ``kernels`` are whole.

    Returns
    -------
    force, w_wheel, w_rail : ndarray, shape (n_steps + 1, k)
        Contact forces (N), wheel and rail displacements under the wheels (m).
    elapsed : float
        Wall time of the loop (s).
    """
    stepper = Newmark(dt)
    M, C, inverse = vehicle_step(vehicle, stepper)
    wheels = vehicle.wheels
    k = len(wheels)
    preload = np.array([w.preload for w in wheels])
    w_rail0 = release[:, :, 0] @ preload + flexibility[phase0] * preload
    u0 = vehicle.static_state(w_rail0 + np.array([w.static_approach for w in wheels]) + r[0])  # r[0]: on a flat
    loads = vehicle.static_loads(u0)
    rows = r.shape[0]
    force, w_wheel, w_rail = np.tile(preload, (rows, 1)), np.empty((rows, k)), np.empty((rows, k))
    w_wheel[0], w_rail[0] = u0[:k], w_rail0
    state = np.zeros((3, u0.size))
    state[0] = u0
    history = np.zeros((k, rows - 1 + kernels.shape[2]))
    loop = convolved_loop(compiled, k == 1 and u0.size == 1)
    n_steps = rows - 1
    r = np.array(r, dtype=float)  # the tail's share is added to it block by block
    arrays = [kernels, pair, release, preload, phase0, flexibility, np.array([w.hertz_constant for w in wheels]), r,
              inverse, M, C, np.array(stepper.coefficients), loads, state, force, w_wheel, w_rail, history,
              np.zeros((k, k + 5))]
    start = time.perf_counter()
    block = max(n_steps, 1) if tail is None else tail.start  # one piece without a tail
    failed = 0
    for first in range(1, n_steps + 1, block):
        last = min(first + block - 1, n_steps)
        share = None if tail is None else tail.response(force, pair, phase0, first, last)
        if share is not None:
            r[first:last + 1] += share
        failed = loop(*arrays, first, last)
        if share is not None:
            w_rail[first:last + 1] += share
        if failed:
            break
    if failed:
        raise RuntimeError(f"the contact forces did not converge at step {failed}")
    return force, w_wheel, w_rail, time.perf_counter() - start
