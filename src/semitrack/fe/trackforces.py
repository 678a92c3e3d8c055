"""What track engineers ask of a run: rail-seat and sleeper-ballast forces at supports, and the rail's bending.

A wheel-rail run records the DOFs these need (:func:`watched_dofs`: the rail node and sleeper of
each watched support, the element under each bending point), and :func:`track_forces` turns
their histories into forces:

- rail seat (the pad): ``F = kv (w_rail - w_sleeper) + c_pad (v_rail - v_sleeper)``, on a slab
  track ``w_sleeper = 0``; compression positive (the rail pressed onto the pad);
- ballast: ``F = kb w_sleeper + c_ballast v_sleeper``, compression positive (under a sleeper
  hanging over a gap, :mod:`semitrack.fe.gaps`, the gap's contact force instead, set by
  :func:`semitrack.wheel_rail_response`);
- the rail's bending moment ``M = -EI dpsi/dx`` at a point, positive sagging (tension at the
  foot), from the element's curvature weights (:func:`semitrack.fe.element.timoshenko_curvature_weights`).

The dampers are the time domain's (:meth:`semitrack.FETrack.matrices`: each family's viscous
equivalent at its reference frequency). The velocities are the average-acceleration rule's own,
``v_{k+1} = 2 (u_{k+1} - u_k) / dt - v_k`` from rest: exactly those the run integrated, rebuilt
from the displacements. The forces are totals, the static preload's share included.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..base.checks import check_int_at_least
from ..base.errors import InputError
from .damping import reference_frequencies
from .element import shear_parameter, timoshenko_curvature_weights
from .models import FETrack

__all__ = ["TrackForces", "Watch", "watched_dofs", "track_forces", "newmark_velocity"]


@dataclass(frozen=True, eq=False)
class TrackForces:
    """Forces in the track during a run.

    Attributes
    ----------
    supports : ndarray of int
        The watched supports' indices k.
    x_supports : ndarray
        Their positions (m).
    rail_seat : ndarray, shape (n_steps + 1, n_supports)
        Pad force (N), compression positive.
    ballast : ndarray or None
        Sleeper-ballast force (N), compression positive; None on a slab track.
    x_bending : ndarray
        Where the bending moment is read (m).
    bending : ndarray, shape (n_steps + 1, n_points)
        The rail's bending moment (N m), positive sagging.
    """

    supports: np.ndarray
    x_supports: np.ndarray
    rail_seat: np.ndarray
    ballast: np.ndarray | None
    x_bending: np.ndarray
    bending: np.ndarray


@dataclass(frozen=True)
class Watch:
    """Which DOFs a run records for :func:`track_forces`, and where each sits in the record."""

    dofs: np.ndarray
    supports: np.ndarray
    rail: np.ndarray
    sleeper: np.ndarray
    x_bending: np.ndarray
    element_rows: np.ndarray
    weights: np.ndarray


def watched_dofs(model: FETrack, supports: Sequence[int] = (), bending_at: ArrayLike = ()) -> Watch:
    """The DOFs to record for the forces at ``supports`` and the bending at ``bending_at``.

    Parameters
    ----------
    model : FETrack
        The model.
    supports : sequence of int
        Support indices k (as :class:`semitrack.InfiniteTrack` numbers them), in the model.
    bending_at : array_like
        Positions on the rail (m) where the bending moment is read.

    Returns
    -------
    Watch
    """
    index = {int(k): i for i, k in enumerate(model.mesh.support_index)}
    ks = np.array([check_int_at_least("supports", k, -10**9) for k in supports], dtype=np.int64)
    missing = [int(k) for k in ks if int(k) not in index]
    if missing:
        raise InputError(f"supports {missing} are not in the model (its supports are {min(index)} to {max(index)})")
    at = [index[int(k)] for k in ks]
    nodes = model.mesh.support_nodes[at]
    rail = model.dofs.index[2 * nodes]
    sleeper = model.dofs.foundation_dof_under(nodes)
    xs = np.atleast_1d(np.asarray(bending_at, dtype=float)).ravel()
    el_dofs, curvature = _curvature(model, xs)
    dofs = np.unique(np.concatenate([rail, sleeper[sleeper >= 0], el_dofs.ravel()[el_dofs.ravel() >= 0]]))
    pos = {int(d): i for i, d in enumerate(dofs)}
    row = np.vectorize(lambda d: pos.get(int(d), -1), otypes=[np.int64])
    return Watch(dofs=dofs, supports=ks, rail=row(rail) if rail.size else rail, sleeper=row(sleeper) if sleeper.size
                 else sleeper, x_bending=xs, element_rows=row(el_dofs) if el_dofs.size else el_dofs, weights=curvature)


def _curvature(model: FETrack, xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The element DOFs (-1 removed) and the weights of ``-EI dpsi/dx`` (N m per unit DOF) at each x."""
    if not xs.size:
        return np.zeros((0, 4), np.int64), np.zeros((0, 4))
    model.points(xs, name="bending_at")  # checks they lie on the rail
    e, xi = model.mesh.locate(xs)
    rail = [model.tracks[p] for p in model.mesh.part[e]]
    EI = np.array([t.E * t.I for t in rail])
    phi = shear_parameter(EI, np.array([t.kappa * t.A * t.G for t in rail]), model.mesh.lengths[e])
    weights = -EI[:, None] * timoshenko_curvature_weights(xi, model.mesh.lengths[e], phi)
    return model.dofs.index[model.mesh.element_dofs()[e]], weights


def newmark_velocity(u: np.ndarray, dt: float) -> np.ndarray:
    """The average-acceleration rule's velocities from its displacements, from rest: ``v_k+1 = 2 du / dt - v_k``.

    Parameters
    ----------
    u : ndarray, shape (n_steps + 1, ...)
        Displacement histories (m).
    dt : float
        Time step (s).

    Returns
    -------
    ndarray
        Velocities (m/s), the shape of ``u``.
    """
    v = np.zeros_like(u)
    du = 2.0 * np.diff(u, axis=0) / dt
    for k in range(du.shape[0]):
        v[k + 1] = du[k] - v[k]
    return v


def track_forces(model: FETrack, watch: Watch, history: np.ndarray, dt: float,
                 f_ref: float | dict | None = None) -> TrackForces:
    """Rail-seat and ballast forces and the rail's bending from the recorded DOFs (see the module docstring).

    Parameters
    ----------
    model : FETrack
        The model of the run.
    watch : Watch
        What was recorded (:func:`watched_dofs`).
    history : ndarray, shape (n_steps + 1, watch.dofs.size)
        The recorded displacements (total: static state included).
    dt : float
        The run's time step (s).
    f_ref : None, float or dict
        The run's reference frequencies of the viscous damping (Hz).

    Returns
    -------
    TrackForces
    """
    velocity = newmark_velocity(history, dt)
    value = lambda rows, X: np.where(rows >= 0, X[:, np.maximum(rows, 0)], 0.0)  # noqa: E731
    index = {int(k): i for i, k in enumerate(model.mesh.support_index)}
    at = np.array([index[int(k)] for k in watch.supports], dtype=np.int64)
    values = model.support_values
    present = values["present"][at]
    kv, kb = values["kv"][at] * present, np.where(present, values["kb"][at], values["kb_track"][at])
    tracks = [model.tracks[p] for p in model.mesh.support_part[at]]
    fr = [reference_frequencies(t, f_ref) for t in tracks]
    c_pad = np.array([t.eta_pad / (2 * np.pi * r["pad"]) for t, r in zip(tracks, fr)]) * kv
    c_bal = np.array([t.eta_ballast / (2 * np.pi * r["ballast"]) for t, r in zip(tracks, fr)]) * kb
    dw, dv = (value(watch.rail, X) - value(watch.sleeper, X) for X in (history, velocity))
    ballast = None
    if any(t.is_ballasted for t in model.tracks):  # a flexible slab's DOFs are no sleepers on ballast
        ballast = kb * value(watch.sleeper, history) + c_bal * value(watch.sleeper, velocity)
    bending = np.einsum("tpj,pj->tp", value(watch.element_rows.ravel(), history).reshape(
        history.shape[0], *watch.element_rows.shape), watch.weights) if watch.x_bending.size else \
        np.zeros((history.shape[0], 0))
    return TrackForces(supports=watch.supports, x_supports=model.x[model.support_nodes[at]],
                       rail_seat=kv * dw + c_pad * dv, ballast=ballast, x_bending=watch.x_bending, bending=bending)
