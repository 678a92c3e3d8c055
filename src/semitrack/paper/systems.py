"""The paper's fitted equivalent systems (Tables 4 and 7) and how well they obey its constraints.

:func:`paper_table4` and :func:`paper_table7` return the systems exactly as printed (three
decimals in the printed scale of each row). :func:`paper_consistency_report` computes how closely
the printed numbers satisfy the constraint relations the paper says it imposed (Eq. 19-20 for
Table 4, Eq. 23 and 28-30 for Table 7) and which characteristic frequencies they imply, with the
deviation that rounding to the printed digits alone could explain.

The printed numbers themselves live in :mod:`semitrack.base.paper_values` (``TABLE4``,
``TABLE7`` and their rounding half-widths), with a note on Table 7's garbled rows.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..base.checks import as_frequencies, as_real_array, check_positive
from ..base.paper_values import (
    CONSTRAINT_FREQUENCIES,
    TABLE4,
    TABLE4_FIT_FREQUENCIES,
    TABLE4_HALF_ULP,
    TABLE7,
    TABLE7_FIT_FREQUENCIES,
    TABLE7_HALF_ULP,
    TABLE7_S1_TRANSPOSED,
)
from ..equivalent.constraints import (
    cell_frequencies,
    inertia_relation,
    lower_spring_relation,
    slab_spring_relation,
    support_mass_relation,
    upper_spring_relation,
)
from ..equivalent.systems import BallastedEquivalent, SlabEquivalent

__all__ = [
    "paper_table4",
    "paper_table7",
    "paper_table7_s1_transposed",
    "paper_consistency_report",
    "table4_consistency",
    "table7_consistency",
    "TABLE4_FIT_FREQUENCIES",
    "TABLE7_FIT_FREQUENCIES",
    "PAPER_FREQUENCIES",
]

#: Characteristic frequencies (Hz) the paper quotes for its constraints
#: (:data:`semitrack.base.paper_values.CONSTRAINT_FREQUENCIES`).
PAPER_FREQUENCIES = CONSTRAINT_FREQUENCIES

_TWO_PI = 2 * np.pi


def paper_table4() -> SlabEquivalent:
    """The slab-track equivalent system of the paper's Table 4 (N = 5), as printed.

    Bars 2 and 4 are massless with zero end springs; ``k_phi``/``c_phi`` have N - 1 = 4 entries.
    """
    return SlabEquivalent(**{key: list(values) for key, values in TABLE4.items()})


def paper_table7() -> BallastedEquivalent:
    """The ballasted-track equivalent system of the paper's Table 7 (N = 5), as printed."""
    return BallastedEquivalent(**{key: list(values) for key, values in TABLE7.items()})


def paper_table7_s1_transposed() -> BallastedEquivalent:
    """Table 7 with its probable misprint corrected: s_1 = 1.081e7 N/m instead of the printed 1.801e7.

    Eq. (23) and (30) both give 1.081e7 N/m for bar 1 (see :func:`table7_consistency`).
    """
    table7 = paper_table7()
    return table7.replace(s=np.r_[TABLE7_S1_TRANSPOSED, table7.parameters()["s"][1:]])


def _rel_dev(printed: np.ndarray, predicted: np.ndarray) -> np.ndarray:
    """(printed - predicted) / predicted, with 0/0 -> 0 and x/0 -> inf."""
    printed, predicted = np.asarray(printed, float), np.asarray(predicted, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = (printed - predicted) / predicted
    out = np.where((predicted == 0) & (printed == 0), 0.0, out)
    return np.where((predicted == 0) & (printed != 0), np.inf, out)


def _rel_ulp(half_ulp: float, values) -> np.ndarray:
    """Relative rounding half-width of printed values (NaN where the value is 0)."""
    values = np.asarray(values, float)
    with np.errstate(divide="ignore"):
        return np.where(values != 0, half_ulp / np.abs(values), np.nan)


def table4_consistency(f_n: float = PAPER_FREQUENCIES["f_n_slab"]) -> dict[str, np.ndarray]:
    """Per-bar check of Table 4 against Eq. (19)-(20) at ``f_n`` (Hz).

    Returns a dict of equal-length arrays (one entry per bar, ready for ``pandas.DataFrame``):
    printed ``k`` and ``J``, their values from Eq. (19)/(20) with the printed ``m`` and ``L``,
    relative deviations, the first-order relative deviation that rounding of the printed
    digits can explain (``*_rounding``), the frequencies implied by the printed numbers,
    ``sqrt(2k/m)`` and ``sqrt(k L^2 / (2J))`` (bounce and pitch of the bar on its springs, Hz),
    and the cell frequencies by eigenvalue solution (Hz). Massless bars give NaN frequencies.
    """
    f_n = float(as_frequencies(check_positive("f_n", f_n), "f_n"))
    p = {k: np.asarray(v, float) for k, v in TABLE4.items()}
    u = TABLE4_HALF_ULP
    m, J, L, k = p["m"], p["J"], p["L"], p["k"]
    k19 = slab_spring_relation(m, f_n)
    J20 = inertia_relation(m, L)
    with np.errstate(divide="ignore", invalid="ignore"):
        f_bounce = np.sqrt(2 * k / m) / _TWO_PI
        f_pitch = np.sqrt(k * L**2 / (2 * J)) / _TWO_PI
    cells = cell_frequencies(paper_table4())
    return {
        "bar": np.arange(1, m.size + 1),
        "m": m,
        "k_printed": k,
        "k_eq19": k19,
        "k_rel_dev": _rel_dev(k, k19),
        "k_rounding": _rel_ulp(u["k"], k) + _rel_ulp(u["m"], m),
        "J_printed": J,
        "J_eq20": J20,
        "J_rel_dev": _rel_dev(J, J20),
        "J_rounding": _rel_ulp(u["J"], J) + _rel_ulp(u["m"], m) + 2 * _rel_ulp(u["L"], L),
        "f_bounce_implied": f_bounce,
        "f_pitch_implied": f_pitch,
        "cell_f1": cells[:, 0],
        "cell_f2": cells[:, 1],
    }


def table7_consistency(f_n1: float = PAPER_FREQUENCIES["f_n1"],
                       f_n2_candidates: Sequence[float] = (PAPER_FREQUENCIES["f_n2_stated"],
                                                           PAPER_FREQUENCIES["f_n2_peak"]),
                       f_anti: float = PAPER_FREQUENCIES["f_anti"]) -> dict[str, np.ndarray]:
    """Per-bar check of Table 7 against Eq. (23), (28)-(30).

    For each candidate ``f_n2`` (Hz) the printed ``k`` is compared with Eq. (29) and the printed
    ``s`` with Eq. (30) (evaluated with the printed ``k``); columns carry the candidate as a
    suffix, e.g. ``k_rel_dev_465``. Independent of the candidate: ``J`` against Eq. (28),
    ``mu`` against Eq. (23) (with printed ``k`` and ``s``), and the frequencies the printed
    numbers imply:

    * ``f_n2_from_k``: the ``f_n2`` that makes Eq. (29) exact for the printed ``k/m``,
    * ``f_n2_from_s``: the ``f_n2`` that makes Eq. (30) exact for the printed ``s/k``,
    * ``f_anti_from_mu``: ``sqrt((k + s)/mu)/(2 pi)``, Eq. (23) solved for the frequency,
    * ``s_from_mu``: ``mu omega_anti^2 - k``, the ``s`` that makes Eq. (23) exact,
    * ``cell_f1..cell_f4``: natural frequencies of each printed unit cell (Hz).
    """
    f_n1, f_anti = (float(as_frequencies(check_positive(k, v), k)) for k, v in (("f_n1", f_n1), ("f_anti", f_anti)))
    f_n2_candidates = as_frequencies(as_real_array(f_n2_candidates, "f_n2_candidates", ndim=1, empty=False),
                                     "f_n2_candidates").tolist()
    p = {k: np.asarray(v, float) for k, v in TABLE7.items()}
    u = TABLE7_HALF_ULP
    m, J, L, k, s, mu = p["m"], p["J"], p["L"], p["k"], p["s"], p["mu"]
    w1 = (_TWO_PI * f_n1) ** 2
    wa = (_TWO_PI * f_anti) ** 2
    J28 = inertia_relation(m, L)
    mu23 = support_mass_relation(k, s, f_anti)
    out = {
        "bar": np.arange(1, m.size + 1),
        "J_printed": J, "J_eq28": J28, "J_rel_dev": _rel_dev(J, J28),
        "J_rounding": _rel_ulp(u["J"], J) + _rel_ulp(u["m"], m) + 2 * _rel_ulp(u["L"], L),
        "mu_printed": mu, "mu_eq23": mu23, "mu_rel_dev": _rel_dev(mu, mu23),
        "mu_rounding": _rel_ulp(u["mu"], mu) + (u["k"] + u["s"]) / (k + s),
    }
    k_round = _rel_ulp(u["k"], k) + _rel_ulp(u["m"], m)
    s_round = _rel_ulp(u["s"], s) + _rel_ulp(u["k"], k)
    for f2 in f_n2_candidates:
        k29 = upper_spring_relation(m, f_n1, f2, f_anti)
        s30 = lower_spring_relation(k, f_n1, f2, f_anti)  # with the printed k: each relation alone
        tag = f"{f2:g}"
        out[f"k_eq29_{tag}"] = k29
        out[f"k_rel_dev_{tag}"] = _rel_dev(k, k29)
        out[f"s_eq30_{tag}"] = s30
        out[f"s_rel_dev_{tag}"] = _rel_dev(s, s30)
    out["k_rounding"] = k_round
    out["s_rounding"] = s_round
    # Eq. (29) solved for omega_n2^2; Eq. (30) solved for omega_n2^2 given s/k.
    out["f_n2_from_k"] = np.sqrt(2 * k / m - w1 + wa) / _TWO_PI
    out["f_n2_from_s"] = np.sqrt(s * (wa - w1) * wa / (s * (wa - w1) - w1 * k)) / _TWO_PI
    out["f_anti_from_mu"] = np.sqrt((k + s) / mu) / _TWO_PI
    out["s_from_mu"] = mu * wa - k
    cells = cell_frequencies(paper_table7())
    for i in range(4):
        out[f"cell_f{i + 1}"] = cells[:, i]
    return out


def paper_consistency_report(f_n: float = PAPER_FREQUENCIES["f_n_slab"],
                             f_n1: float = PAPER_FREQUENCIES["f_n1"],
                             f_n2_candidates: Sequence[float] = (PAPER_FREQUENCIES["f_n2_stated"],
                                                                 PAPER_FREQUENCIES["f_n2_peak"]),
                             f_anti: float = PAPER_FREQUENCIES["f_anti"]) -> dict[str, dict[str, np.ndarray]]:
    """Both checks: ``{"table4": table4_consistency(f_n), "table7": table7_consistency(...)}``.

    Each value is a dict of per-bar arrays (``pandas.DataFrame(report["table4"])`` gives a
    table). The defaults are the paper's values (:data:`PAPER_FREQUENCIES`).

    Parameters
    ----------
    f_n : float
        Table 4: the slab track's first resonance used in Eq. (19) (Hz).
    f_n1 : float
        Table 7: the first repeated frequency omega_n1 / 2 pi of the unit cell (Hz).
    f_n2_candidates : sequence of float
        Table 7: the values of the second repeated frequency to test (Hz).
    f_anti : float
        Table 7: the anti-resonance omega_anti / 2 pi of Eq. (23) (Hz).
    """
    return {"table4": table4_consistency(f_n),
            "table7": table7_consistency(f_n1=f_n1, f_n2_candidates=f_n2_candidates, f_anti=f_anti)}
