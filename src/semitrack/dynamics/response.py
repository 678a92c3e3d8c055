"""One labelled result for every simulation: times and named channels (after python-control's
``TimeResponseData``)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = ["TimeResponse"]


@dataclass(frozen=True, eq=False)
class TimeResponse:
    """The output of :func:`semitrack.dynamics.simulate.simulate`.

    Attributes
    ----------
    t : ndarray, shape (n_steps + 1,)
        Times (s), from 0.
    channels : dict of str to ndarray
        Each recorded quantity, shape ``(n_steps + 1, n_columns)``: ``"dofs"`` (the recorded
        DOFs, m or rad), one entry per probe set by its name (m or rad), and with contacts
        ``"contact force"`` (N), ``"wheel"`` and ``"rail"`` (displacements at the contacts, m).
    labels : dict of str to tuple of str
        A label per column of each channel.
    elapsed : float
        Wall time of the step loop (s), set-up excluded.
    compiled : bool
        Whether the compiled loop ran (else the NumPy reference loop).
    """

    t: np.ndarray
    channels: Mapping[str, np.ndarray]
    labels: Mapping[str, tuple] = field(default_factory=dict)
    elapsed: float = 0.0
    compiled: bool = False

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.channels[name]
        except KeyError:
            raise KeyError(f"no channel {name!r}; the channels are {list(self.channels)}") from None

    @property
    def dt(self) -> float:
        """The time step (s)."""
        return float(self.t[1] - self.t[0])
