"""The exact method: periodic-structure (Bloch-wave) theory on one period of the track.

Cut the infinite periodic track at a cross-section x_c and view it as a chain of identical
periods. The dynamic stiffness D of one period maps the displacements (w, psi) of its two end
cross-sections a = x_c + nL and b = x_c + (n+1)L to the loads applied there; it is built from
exact rail segments between the supports (each wave of the Timoshenko field equation referred to
the end it decays away from, :func:`semitrack.model.timoshenko.segment_dynamic_stiffness`) with
the supports condensed out. Equilibrium of the node between two periods gives the Bloch
recurrence

    D_ba u_n + (D_aa + D_bb) u_{n+1} + D_ab u_{n+2} = 0.

Its waves u_{n+1} = lambda u_n come in pairs (lambda, 1/lambda) (Mead's periodic-structure
theory). On the semi-infinite track x > x_c only the two that decay to the right exist:
u_{n+1} = G u_n with G the solvent of D_ba + (D_aa + D_bb) G + D_ab G^2 = 0 whose eigenvalues
satisfy |lambda| < 1, which cyclic reduction finds in a few doubling steps. Then

    K_R = D_aa + D_ab G      (end stiffness of the track x > x_c),  alpha = K_R^{-1},

and likewise K_L for the track x < x_c. Nothing is truncated: no wavenumber range, no finite
differences, no sum over j.

Why not the period's transfer matrix T (s(x_c + L) = T s(x_c) for s = (w, psi, Q, M)), whose
eigenvectors give the same waves? T holds e^{kL} beside e^{-kL}: once the evanescent waves grow
by ~1e8 over a period (long spacing, very stiff pads or shear, MHz frequencies), the decaying
waves drown in its rounding error and alpha comes out non-reciprocal. D stays bounded.

Without damping a wave has |lambda| = 1 and the reduction does not converge; the answer is then
the limit of vanishing damping (the wave that carries power away from the cut), computed with a
rail loss factor of 1e-9 added, far below any physical one.
"""

from __future__ import annotations

import functools

import numpy as np

from ..base.checks import check_real
from ..base.errors import InputError
from ..model.timoshenko import segment_dynamic_stiffness
from ..model.tracks import PeriodicCell, Track

# Cyclic reduction: doubling steps allowed (a wave with |lambda| = 1 - 1e-12 needs ~46), and the
# relative size of the last correction at which it has converged.
_MAX_DOUBLINGS = 64
_CONVERGED = 1e-15
# Rail loss factor standing in for "vanishing damping" where the track has none.
VANISHING_DAMPING = 1e-9


def vanishing_damping(track: Track) -> float:
    """The rail loss factor added for the limit of vanishing damping: :data:`VANISHING_DAMPING` for a
    rail with less than that, else 0 (a damped rail is taken as it is)."""
    return VANISHING_DAMPING if track.eta_rail < VANISHING_DAMPING else 0.0


# An end stiffness is refused when K12 and K21 differ by more than this (relative), or when it
# generates power beyond this (relative) rounding level.
_RECIPROCITY_TOL = 1e-6
_PASSIVITY_TOL = 1e-9


def period_dynamic_stiffness(cell: PeriodicCell, omega: np.ndarray, x_cut: float,
                             extra_loss: float = 0.0) -> np.ndarray:
    """Dynamic stiffness of one period between its end cross-sections x_cut and x_cut + L.

    Parameters
    ----------
    cell : PeriodicCell
        The period. If its foundation couples supports (a flexible slab), ``x_cut`` must be
        the cell's :attr:`~semitrack.PeriodicCell.joint`, where no coupling crosses.
    omega : ndarray
        Circular frequencies (rad/s), shape ``(n,)``.
    x_cut : float
        Start of the period (m). A support exactly at ``x_cut`` belongs to the period's right
        end: it is the period's last support, on the left-hand part of a cut there.
    extra_loss : float
        Loss factor added to the rail's (-), as in
        :func:`semitrack.model.timoshenko.segment_dynamic_stiffness`.

    Returns
    -------
    ndarray, shape (n, 4, 4)
        Maps (w_a, psi_a, w_b, psi_b) at x_cut and x_cut + L (m, rad) to the loads applied to the
        period there (N, N m); the rail segments are exact and the supports condensed out.
    """
    k, _, _ = _period_model(cell, omega, x_cut, extra_loss)
    n_dofs = k.shape[-1]
    ends = np.r_[0, 1, n_dofs - 2, n_dofs - 1]
    inner = np.arange(2, n_dofs - 2)
    d = k[:, ends[:, None], ends]
    if inner.size:
        d = d - k[:, ends[:, None], inner] @ np.linalg.solve(k[:, inner[:, None], inner], k[:, inner[:, None], ends])
    return d


def _period_model(cell: PeriodicCell, omega: np.ndarray, x_cut: float, extra_loss: float,
                  point: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Assembled stiffness of the period from ``x_cut``, before condensation.

    Rail nodes sit at both ends, at every support and at ``point`` (m, inside the period) if
    given. Returns the stiffness ``(n, 2 n_nodes, 2 n_nodes)`` over (w, psi) of the nodes in
    order along x, the node positions relative to ``x_cut`` (m), and the rail segments'
    dynamic stiffness ``(n_nodes - 1, n, 4, 4)``.
    """
    f = omega / (2 * np.pi)
    period = cell.period
    ks = cell.support_stiffness_matrix(f)  # (n, 2S, 2S)
    if _couples_supports(ks) and not same_section(x_cut, cell.joint, period):
        raise InputError(
            f"the foundation of this cell couples its supports: its period must start at the joint "
            f"x = {cell.joint:g} m, where no coupling crosses, not at x = {x_cut:g} m")
    offsets = [_distance_past(x, x_cut, period) for x in cell.positions]
    points = [dist for dist in offsets if dist < period]
    if point is not None:
        at = _distance_past(point, x_cut, period)
        # A point within rounding of a support is that support's node, not a segment of ~0 length.
        near = [p for p in points if abs(p - at) <= 1e-9 * period]
        points.append(near[0] if near else at)
    edges = np.unique(np.r_[0.0, points, period])
    segments = segment_dynamic_stiffness(cell.track, omega, np.diff(edges), extra_loss)  # (m, n, 4, 4)
    n_nodes = edges.size
    k = np.zeros((omega.size, 2 * n_nodes, 2 * n_nodes), dtype=complex)
    for j, seg in enumerate(segments):
        k[:, 2 * j : 2 * j + 4, 2 * j : 2 * j + 4] += seg
    nodes = np.searchsorted(edges, offsets)  # the node at each support (the last if at L)
    dofs = np.ravel(np.column_stack([2 * nodes, 2 * nodes + 1]))  # (w, psi) of each support, in ks order
    k[:, dofs[:, None], dofs] += ks
    return k, edges, segments


def _couples_supports(ks: np.ndarray) -> bool:
    """True when a support stiffness matrix ``(n, 2S, 2S)`` links two different supports."""
    s = ks.shape[-1] // 2
    own = np.kron(np.eye(s, dtype=bool), np.ones((2, 2), dtype=bool))
    return bool(np.any(ks[:, ~own] != 0))


def same_section(x: float, y: float, period: float) -> bool:
    """True when ``x`` and ``y`` (m) are the same cross-section of the periodic track."""
    gap = (x - y) % period
    return min(gap, period - gap) <= 1e-9 * period


def _distance_past(x: float, x_cut: float, period: float) -> float:
    """Distance (m) from x_cut forward to the next support image of x, in (0, period].

    A support within 1e-9 periods of the cut counts as at the cut (distance ``period``): a
    rail segment of rounding-error length would have an unbounded dynamic stiffness.
    """
    dist = (x - x_cut) % period
    return period if dist < 1e-9 * period or dist > (1 - 1e-9) * period else dist


def cyclic_reduction(d: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Solvents of the Bloch recurrence of a chain of periods with dynamic stiffness ``d``.

    Returns ``g_right`` (u_{n+1} = g_right u_n for the waves decaying towards +x), ``g_left``
    (u_{n-1} = g_left u_n for those decaying towards -x), both ``(n, 2, 2)``, and a boolean mask
    of the frequencies where the reduction converged (it cannot where a wave has |lambda| = 1).
    """
    d_aa, d_ab, d_ba, d_bb = d[:, :2, :2], d[:, :2, 2:], d[:, 2:, :2], d[:, 2:, 2:]
    a0, a1, a2 = d_ba, d_aa + d_bb, d_ab  # a0 + a1 G + a2 G^2 = 0 for the right-decaying G
    hat_right, hat_left = a1.copy(), a1.copy()
    converged = np.zeros(d.shape[0], dtype=bool)
    with np.errstate(all="ignore"):  # undamped waves make the iterates grow: reported as not converged
        for _ in range(_MAX_DOUBLINGS):
            inv_a1 = np.linalg.inv(a1)
            t0, t2 = inv_a1 @ a0, inv_a1 @ a2
            corr_right, corr_left = a2 @ t0, a0 @ t2
            hat_right, hat_left = hat_right - corr_right, hat_left - corr_left
            a1 = a1 - corr_right - corr_left
            a0, a2 = -a0 @ t0, -a2 @ t2
            size = np.maximum(_norm(corr_right) / _norm(hat_right), _norm(corr_left) / _norm(hat_left))
            converged = size <= _CONVERGED  # False where NaN
            if converged.all():
                break
        ok = converged & np.isfinite(hat_right).all(axis=(1, 2)) & np.isfinite(hat_left).all(axis=(1, 2))
        hat_right[~ok], hat_left[~ok] = np.eye(2), np.eye(2)  # placeholders, replaced by the caller
        g_right = -np.linalg.solve(hat_right, d_ba)
        g_left = -np.linalg.solve(hat_left, d_ab)
    return g_right, g_left, ok


def _norm(a: np.ndarray) -> np.ndarray:
    return np.sqrt(np.sum(np.abs(a) ** 2, axis=(-2, -1)))


def end_stiffness(cell: PeriodicCell, omega: np.ndarray, x_cut: float) -> tuple[np.ndarray, np.ndarray]:
    """Dynamic stiffness of the two semi-infinite tracks on either side of a cut at ``x_cut``.

    Parameters
    ----------
    cell : PeriodicCell
        The period of the track. If its foundation couples supports, ``x_cut`` must be its
        joint (see :func:`period_dynamic_stiffness`).
    omega : ndarray
        Circular frequencies (rad/s), shape ``(n,)``.
    x_cut : float
        Position of the cut (m), in the coordinates of ``cell.positions``.

    Returns
    -------
    k_right, k_left : ndarray, shape (n, 2, 2)
        ``k_right`` maps (w, psi) at the end of the track x > x_cut to the loads (Q, M) applied
        to it there; ``k_left`` likewise for the track x < x_cut (loads applied to that part).
        Units: N/m, N/rad, N m/m, N m/rad.

    Raises
    ------
    ValueError
        Where the result cannot be trusted: the algebra overflowed, the doubling did not
        converge, or an end stiffness is not reciprocal (to 1e-6) and passive (to 1e-9 of its
        size), signs of lost precision. None happens for tracks within a wide margin of physical
        ones (spacing 0.3-12 m, up to 50 MHz, pads up to 1e25: tested).
    """
    check_real("x_cut", x_cut)
    omega = np.atleast_1d(omega)
    # Without rail damping a wave may keep |lambda| = 1 (above the shear cut-on, two may) and the
    # doubling would stall or settle on a wrong solvent: take the limit of vanishing damping.
    extra_loss = vanishing_damping(cell.track)
    # Overflow warnings would only precede the clearer error below: every result is checked.
    with np.errstate(all="ignore"):
        try:
            d = period_dynamic_stiffness(cell, omega, x_cut, extra_loss)
            g_right, g_left, converged = cyclic_reduction(d)
            k_right = d[:, :2, :2] + d[:, :2, 2:] @ g_right
            k_left = d[:, 2:, 2:] + d[:, 2:, :2] @ g_left
            good = converged & _physical(k_right) & _physical(k_left)
        except np.linalg.LinAlgError:  # inf or NaN in the algebra, e.g. kappa = 1e300
            good = np.zeros(omega.size, dtype=bool)
    if not good.all():
        raise _unresolved(cell, omega[~good])
    return k_right, k_left


def _unresolved(cell: PeriodicCell, omega_bad: np.ndarray) -> InputError:
    f_bad = omega_bad / (2 * np.pi)
    return InputError(
        f"the exact method cannot resolve {cell.track.name!r} at {f_bad.size} frequencies from "
        f"{f_bad.min():.6g} Hz: the doubling did not converge or its end stiffness is not reciprocal "
        "and passive (lost precision); the track's parameters are outside what the method resolves")


def _physical(k: np.ndarray) -> np.ndarray:
    """Mask of the 2x2 end stiffnesses that are reciprocal (K12 = K21) and passive (they absorb power).

    A wrong one is the sign of lost precision or of a wrong solvent.
    """
    # K12 (N/rad) and K21 (N m/m) share their unit; sqrt(|K11 K22|) is the scale they live on
    # (K12 alone may vanish, e.g. at a cut on a symmetry plane).
    scale = np.sqrt(np.abs(k[:, 0, 0] * k[:, 1, 1]))
    reciprocal = np.abs(k[:, 0, 1] - k[:, 1, 0]) <= _RECIPROCITY_TOL * scale
    # Power absorbed by the end, (omega/2) u^H [(K - K^H) / 2i] u: that matrix must be >= 0. Its
    # units differ per entry: judge it after the congruence diag(c, 1) K diag(c, 1) with
    # c = sqrt(|K22 / K11|), which balances the diagonal and keeps the sign of the quadratic form.
    c = np.sqrt(np.abs(k[:, 1, 1] / k[:, 0, 0]))[:, None, None]
    balanced = k * np.array([[1.0, 0.0], [0.0, 0.0]]) * c**2 + k * np.array([[0.0, 1.0], [1.0, 0.0]]) * c
    balanced[:, 1, 1] = k[:, 1, 1]
    absorbed = np.linalg.eigvalsh((balanced - np.conj(np.swapaxes(balanced, 1, 2))) / 2j)
    passive = absorbed[:, 0] >= -_PASSIVITY_TOL * np.abs(balanced).max(axis=(1, 2))
    return reciprocal & passive


def slab_cut_end_stiffness(cell: PeriodicCell, omega: np.ndarray) -> np.ndarray:
    """End stiffness of the track right of a cut inside a flexible slab, the slab cut there too.

    The cut is the cell's central cross-section, the k-th mid-span of a slab (k =
    ``slab.cut_span`` >= 1). The part x > x_cut is the rest of the cut slab (free at the cut,
    carrying the slab's last S - k fasteners, with its rail) followed by the semi-infinite track
    from the next joint, whose end stiffness :func:`end_stiffness` gives; it is solved whole and
    condensed onto the rail at the cut. Unlike Eq. (14) from the infinite track's responses,
    which presumes the two halves meet through the rail alone, this is the end of a structure:
    reciprocal and passive.

    Parameters
    ----------
    cell : PeriodicCell
        The cell of a flexible-slab track (``track.cell()``).
    omega : ndarray
        Circular frequencies (rad/s), shape ``(n,)``.

    Returns
    -------
    ndarray, shape (n, 2, 2)
        Maps (w, psi) at the cut (m, rad) to the loads (Q, M) applied there (N, N m).
    """
    track = cell.track
    slab, d = track.slab, track.spacing
    k = slab.cut_span
    n_right = slab.fasteners - k
    omega = np.atleast_1d(omega)
    k_next, _ = end_stiffness(cell, omega, cell.joint)  # the track beyond the cut slab's far joint
    rest = PeriodicCell(track, n_right * d, tuple(d * (np.arange(n_right) + 0.5)),
                        foundation=functools.partial(track.slab_receptance, from_span=k))
    extra_loss = vanishing_damping(track)
    with np.errstate(all="ignore"):
        try:
            stiff, _, _ = _period_model(rest, omega, 0.0, extra_loss)  # from the cut to the joint
            stiff[:, -2:, -2:] += k_next
            inner = np.arange(2, stiff.shape[-1])
            k_end = stiff[:, :2, :2] - stiff[:, :2, inner] @ np.linalg.solve(stiff[:, inner[:, None], inner],
                                                                             stiff[:, inner, :2])
            good = _physical(k_end)
        except np.linalg.LinAlgError:
            good = np.zeros(omega.size, dtype=bool)
    if not good.all():
        raise _unresolved(cell, omega[~good])
    return k_end


def infinite_response(cell: PeriodicCell, omega: np.ndarray, x: float) -> tuple[np.ndarray, np.ndarray]:
    """Response of the infinite track to a unit force and a unit moment on the rail at ``x``.

    Parameters
    ----------
    cell : PeriodicCell
        The period of the track.
    omega : ndarray
        Circular frequencies (rad/s), shape ``(n,)``.
    x : float
        Load position (m), in the coordinates of ``cell.positions``.

    Returns
    -------
    h : ndarray, shape (n, 2, 2)
        Receptance at x: (w, psi) (m, rad) per load (F, M) (N, N m); H = (K_R + K_L)^{-1}.
    loads_right : ndarray, shape (n, 2, 2)
        The rail's internal forces (Q, M) just right of x per load: the loads the rail x > x
        carries, Q2 and M1 of the paper's Eq. (14) among them.

    Notes
    -----
    Where no foundation coupling crosses x, the two semi-infinite tracks either side of x have
    end stiffnesses K_R and K_L (:func:`end_stiffness`). Inside a flexible slab the slab links
    both sides, so the slab's period holding x is solved with the semi-infinite tracks beyond its
    joints attached as K_L and K_R, and the forces come from the exact rail segment right of x.
    """
    omega = np.atleast_1d(omega)
    joint = cell.joint
    f = omega / (2 * np.pi)
    if same_section(x, joint, cell.period) or not _couples_supports(cell.support_stiffness_matrix(f[:1])):
        k_right, k_left = end_stiffness(cell, omega, x)
        h = np.linalg.inv(k_right + k_left)
        return h, k_right @ h
    k_right, k_left = end_stiffness(cell, omega, joint)
    extra_loss = vanishing_damping(cell.track)
    with np.errstate(all="ignore"):
        k, edges, segments = _period_model(cell, omega, joint, extra_loss, point=x)
        k[:, :2, :2] += k_left  # the track before the slab's first joint
        k[:, -2:, -2:] += k_right  # and after its second (the same track, by periodicity)
        node = int(np.argmin(np.abs(edges - _distance_past(x, joint, cell.period))))  # the point's node
        unit = np.zeros((k.shape[-1], 2))
        unit[2 * node: 2 * node + 2] = np.eye(2)
        try:
            u = np.linalg.solve(k, np.broadcast_to(unit, (omega.size,) + unit.shape))
            h = u[:, 2 * node: 2 * node + 2]
            loads_right = segments[node][:, :2, :] @ u[:, 2 * node: 2 * node + 4]
            good = _physical(np.linalg.inv(h))
        except np.linalg.LinAlgError:
            good = np.zeros(omega.size, dtype=bool)
    if not good.all():
        raise _unresolved(cell, omega[~good])
    return h, loads_right


def infinite_receptance(cell: PeriodicCell, omega: np.ndarray, x: float) -> np.ndarray:
    """2x2 receptance of the infinite track at ``x`` (response (w, psi) to load (F, M) at x).

    Shape ``(n, 2, 2)``; see :func:`infinite_response`.
    """
    return infinite_response(cell, omega, x)[0]
