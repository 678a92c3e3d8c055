"""A run's figures as an engineer reads them: the peaks, minima and rms of each wheel's contact force
and the peaks in the track, beside a reference run's.

:func:`run_summary` (and :meth:`semitrack.ContactResponse.summary`) makes one long table, a row
per item and quantity, so that a wheel's force and a support's force sit in one table with the
same columns and a reference run's values and ratios beside them.
"""

from __future__ import annotations

import numpy as np

from ..base.checks import check_real
from ..base.errors import InputError, InputTypeError

__all__ = ["run_summary"]


def _stats(label: str, values: np.ndarray) -> list[tuple[str, str, float]]:
    """Peak, minimum and rms (kN) of one force history."""
    return [(label, "peak force (kN)", float(values.max()) / 1e3),
            (label, "minimum force (kN)", float(values.min()) / 1e3),
            (label, "rms force (kN)", float(np.sqrt(np.mean(values ** 2))) / 1e3)]


def _rows(response, after: float) -> list[tuple[str, str, float]]:
    """(item, quantity, value) of every figure of the run, from ``after`` (s) on."""
    late = response.t >= after
    force = response.force.reshape(response.t.size, -1)
    names = response.vehicle.wheel_names if response.vehicle is not None else ("wheel",)
    rows = []
    for name, static, history in zip(names, force[0], force[late].T):
        rows += _stats(name, history)
        rows.append((name, "static force (kN)", float(static) / 1e3))
        rows.append((name, "peak / static (-)", float(history.max() / static) if static > 0 else np.nan))
        rows.append((name, "time out of contact (ms)", 1e3 * response.dt * int(np.count_nonzero(history <= 0))))
    forces = response.track_forces
    if forces is not None:
        for j, k in enumerate(forces.supports):
            rows.append((f"support {k}", "peak rail-seat force (kN)", float(forces.rail_seat[late, j].max()) / 1e3))
            if forces.ballast is not None:
                rows.append((f"support {k}", "peak ballast force (kN)", float(forces.ballast[late, j].max()) / 1e3))
        for j, x in enumerate(forces.x_bending):
            rows.append((f"rail at x = {x:.3g} m", "peak sagging moment (kN m)",
                         float(forces.bending[late, j].max()) / 1e3))
    gaps = response.gaps
    if gaps is not None:
        for j, k in enumerate(gaps.supports):
            item = f"hanging sleeper {k} (gap {1e3 * gaps.gaps[j]:.3g} mm)"
            rows.append((item, "peak ballast force (kN)", float(gaps.force[late, j].max()) / 1e3))
            rows.append((item, "time on the ballast (ms)", 1e3 * float(gaps.contact_time[j])))  # the whole run
    return rows


def run_summary(response, reference=None, after: float | None = None):
    """The figures of a run engineers read, a row per item and quantity, beside a reference run's.

    Parameters
    ----------
    response : ContactResponse
        The run (any route).
    reference : ContactResponse, optional
        A run to compare with (the same vehicle on the perfect track, say): its values and the
        ratio ``value / reference`` join the table; items it lacks read NaN.
    after : float, optional
        The statistics are taken from this time on (s); by default from the end of the
        roughness's fade-in (``response.ramp``), where the roughness acts in full. The static
        force is the run's first sample (the static start) either way.

    Returns
    -------
    pandas.DataFrame
        Indexed by ``(item, quantity)``: items are the wheels as the vehicle names them
        (``leading wheel``, ``trailing wheel`` of a bogie; ``wheel 1``, ... of wheels on their
        own), the watched supports (``support k``: peak rail-seat and ballast force), the points
        of the rail's bending and the hanging sleepers. Column ``value``; with a reference
        ``reference`` and ``ratio``.
    """
    import pandas as pd  # the tables' library, imported for a table only

    if type(response).__name__ != "ContactResponse":  # the class imports this module: its name, not the class
        raise InputTypeError(f"response must be a ContactResponse (a run's result), got {type(response).__name__}")
    start = response.ramp if after is None else check_real("after", after)
    if not np.count_nonzero(response.t >= start) >= 1:
        raise InputError(f"after={start:.6g} s leaves no sample of a {response.t[-1]:.6g} s run")
    rows = _rows(response, start)
    table = pd.DataFrame(rows, columns=["item", "quantity", "value"]).set_index(["item", "quantity"])
    if reference is None:
        return table
    if type(reference).__name__ != "ContactResponse":
        raise InputTypeError(f"reference must be a ContactResponse (the run to compare with), got "
                             f"{type(reference).__name__}")
    if len(reference.wheels or (reference.wheel,)) != len(response.wheels or (response.wheel,)):
        raise InputError(f"reference must run the same number of wheels ({len(response.wheels or (response.wheel,))}), "
                         f"got {len(reference.wheels or (reference.wheel,))}: its figures would be another vehicle's")
    theirs = start if after is not None else reference.ramp
    if not np.count_nonzero(reference.t >= theirs) >= 1:
        raise InputError(f"reference: after={theirs:.6g} s leaves no sample of its {reference.t[-1]:.6g} s run")
    other = pd.DataFrame(_rows(reference, theirs),
                         columns=["item", "quantity", "reference"]).set_index(["item", "quantity"])
    table = table.join(other, how="left")
    with np.errstate(divide="ignore", invalid="ignore"):
        table["ratio"] = table["value"] / table["reference"]
    return table
