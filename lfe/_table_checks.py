"""Checks of a raw table's columns, each a ``ValueError`` naming the place, table, column and row.

``where`` names the place (``"scenario 's1' (index 0)"``) and ``name`` the table, as
:func:`lfe.scenario.check_scenario` reports them.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["check_frame", "check_numeric", "check_values"]


def check_frame(frame, name, columns, where):
    """``frame`` is a DataFrame with every column of ``columns``."""
    if not isinstance(frame, pd.DataFrame):
        raise ValueError(f"{where}: {name} must be a pandas DataFrame, got {type(frame).__name__}")
    missing = [c for c in columns if c not in frame.columns]
    if missing:
        raise ValueError(
            f"{where}: {name} is missing column {missing[0]!r} (needs {list(columns)})"
        )


def check_numeric(frame, name, columns, where):
    """Every value of ``columns`` is a finite number (or text that reads as one)."""
    for c in columns:
        values = pd.to_numeric(frame[c], errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(values)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"{where}: {name} column {c!r} has a non-numeric or non-finite value "
                f"{frame[c].iloc[row]!r} at row {row}"
            )


def check_values(frame, name, column, allowed, where):
    """Every value of ``column`` is one of ``allowed``."""
    values = frame[column]
    ok = values.isin(allowed).to_numpy()
    if not ok.all():
        values = values.astype(object).to_numpy()
        row = int(np.flatnonzero(~ok)[0])
        raise ValueError(
            f"{where}: {name} column {column!r} has unknown value {values[row]!r} at row {row}; "
            f"expected one of {list(allowed)}"
        )
