"""Wheels on an FE track model: their static start and their contacts, shared by the FE model and window routes.

The FE model route (:mod:`.fe_model`) sets them up once on the model that holds the whole path;
the window route (:mod:`.window_model`) once per window it moves to.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..dynamics.contact import HertzContacts
from ..dynamics.factor import factorise
from ..dynamics.points import PointSet
from ..fe.gaps import GapResponse, SleeperGaps, contact_time, static_with_gaps
from ..fe.models import FETrack
from ..model.vehicle import Vehicle
from ..model.wheel import Wheel

__all__ = ["static_start", "all_contacts", "gap_response", "contact_points"]


def static_start(model: FETrack, vehicle: Vehicle, K: sp.csc_matrix, contacts: PointSet,
                  flexibility: np.ndarray, gaps: SleeperGaps | None, r0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The static equilibrium under the preloads with the contacts at their first positions.

    ``flexibility`` is the rail elements' own deflection under each contact at the start (m/N);
    hanging sleepers rest on their ballast where the preloads close their gaps; ``r0`` is each
    wheel's input at the start (m: a wheel may start standing on its flat).
    Returns the state ``u0`` (model DOFs, then the vehicle's) and the constant loads on the
    vehicle's DOFs (:meth:`semitrack.model.vehicle.Vehicle.static_loads`: each contact at its
    wheel's preload, a suspension to a still bogie carrying none of it).
    """
    n, wheels = model.n_dof, vehicle.wheels
    preload = np.array([w.preload for w in wheels])
    load = contacts.matrix(n, 0).T @ preload
    u_track = factorise(K).solve(load) if gaps is None else static_with_gaps(K, load, gaps)
    w0 = contacts.values(u_track, 0) + flexibility * preload + np.array([w.static_approach for w in wheels]) + r0
    u_vehicle = vehicle.static_state(w0)
    return np.concatenate([u_track, u_vehicle]), vehicle.static_loads(u_vehicle)


def all_contacts(wheel_dofs: np.ndarray, points: PointSet, wheels: tuple[Wheel, ...], r: np.ndarray,
                  flexibility: np.ndarray, gaps: SleeperGaps | None) -> HertzContacts:
    """The wheels' Hertzian contacts, then each hanging sleeper's unilateral ballast (:mod:`.gaps`)."""
    c_h = [w.hertz_constant for w in wheels]
    if gaps is None:
        return HertzContacts(wheel_dofs, points, c_h, r, compliance=flexibility)
    rows = points.dofs.shape[0]
    return HertzContacts(np.concatenate([wheel_dofs, gaps.dofs]), PointSet.stacked([points, gaps.points(rows)]),
                         np.concatenate([c_h, gaps.stiffness]), np.hstack([r, np.tile(gaps.gaps, (r.shape[0], 1))]),
                         labels=tuple(f"wheel {i}" for i in range(len(wheels))) + tuple(
                             f"ballast under support {k}" for k in gaps.supports),
                         compliance=np.hstack([flexibility, np.zeros((rows, gaps.n))]),
                         linear=np.r_[np.zeros(len(wheels), bool), np.ones(gaps.n, bool)])


def gap_response(res, gaps: SleeperGaps, k: int, dt: float) -> GapResponse:
    """The hanging sleepers' columns of a run's contact channels (after the k wheels')."""
    force, w = res["contact force"][:, k:], res["wheel"][:, k:]
    return GapResponse(supports=gaps.supports, gaps=gaps.gaps, force=force, opening=gaps.gaps - w,
                       contact_time=contact_time(force, dt))


def contact_points(model: FETrack, x: np.ndarray, moving: bool) -> PointSet:
    """The wheels' contact points: fixed at ``x[0]``, or along their paths ``x`` (steps, wheels)."""
    if not moving:
        return model.points(x[0])
    return PointSet.stacked(model.points(x[:, i], moving=True) for i in range(x.shape[1]))
