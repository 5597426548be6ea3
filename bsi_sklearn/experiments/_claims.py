"""The paper's claims beside our measured values, and the Markdown tables that show them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = ["Claim", "claims_frame", "fraction_by_size", "mean_at", "select"]

PASS, FALL_SHORT, NOT_MEASURED = "PASS", "FALL SHORT", "NOT MEASURED"


@dataclass(frozen=True)
class Claim:
    """One claim of the paper and the value we measured for it.

    Parameters
    ----------
    id : str
        Short identifier, e.g. ``"S2-top5"``.
    experiment : str
        Where the claim is made (``"synthetic, scenario 2"``).
    paper : str
        The claim, in the paper's words or close to them.
    criterion : str
        How the measured value is tested.
    measured : str
        The measured value, readable.
    value : float
        The number the criterion is applied to.
    passed : bool or None
        Whether the criterion holds, computed from the results (never set by hand); None
        when the run did not measure it (e.g. no training size of 10 or more).
    """

    id: str
    experiment: str
    paper: str
    criterion: str
    measured: str
    value: float
    passed: bool | None

    @property
    def status(self):
        """``"PASS"``, ``"FALL SHORT"`` or ``"NOT MEASURED"``."""
        if self.passed is None:
            return NOT_MEASURED
        return PASS if self.passed else FALL_SHORT

    @classmethod
    def not_measured(cls, id, experiment, paper, criterion, reason):
        """A claim this run could not test, with the reason."""
        return cls(id, experiment, paper, criterion, f"not measured ({reason})", float("nan"),
                   None)


def claims_frame(claims):
    """The claims as a DataFrame with a ``status`` column (PASS / FALL SHORT / NOT MEASURED).

    Examples
    --------
    >>> c = Claim("x", "demo", "over 0.9", "mean > 0.9", "0.95", 0.95, 0.95 > 0.9)
    >>> claims_frame([c])[["id", "value", "status"]]
      id  value status
    0  x   0.95   PASS
    """
    rows = [{"id": c.id, "experiment": c.experiment, "paper": c.paper,
             "criterion": c.criterion, "measured": c.measured, "value": float(c.value),
             "status": c.status} for c in claims]
    return pd.DataFrame(rows, columns=["id", "experiment", "paper", "criterion", "measured",
                                       "value", "status"])


def select(frame, **conditions):
    """Rows of ``frame`` whose columns equal the given values (a value may be a tuple: any of).

    Raises ``ValueError`` when nothing matches, so that a claim is never computed on an
    empty selection.
    """
    mask = np.ones(len(frame), dtype=bool)
    for column, value in conditions.items():
        if isinstance(value, (tuple, list, set, frozenset)):
            mask &= frame[column].isin(list(value)).to_numpy()
        else:
            mask &= (frame[column] == value).to_numpy()
    out = frame[mask]
    if out.empty:
        raise ValueError(f"no results match {conditions}")
    return out


def mean_at(summary, metric, size, **filters):
    """The mean of ``metric`` at training size ``size`` in the one matching summary row."""
    rows = select(summary, size=size, **filters)
    if len(rows) != 1:
        raise ValueError(f"{len(rows)} summary rows match size={size}, {filters}; expected 1")
    return float(rows[f"{metric}_mean"].iloc[0])


def fraction_by_size(results, metric, **filters):
    """Fraction of the matching fits where the boolean ``metric`` holds, overall and per size.

    Returns
    -------
    fraction : float
    text : str
        ``"k/n fits (size: fraction, ...)"``.
    """
    rows = select(results, **filters)
    per = rows.groupby("size")[metric].mean()
    text = (f"{int(rows[metric].sum())}/{len(rows)} fits (by n: "
            + ", ".join(f"{n}: {v:.0%}" for n, v in per.items()) + ")")
    return float(rows[metric].mean()), text
