"""Recurrent baselines of the paper's large-force-exercise comparison (LSTM, Bi-LSTM, coupled)."""

from baselines.lstm import (
    PAPER_BASELINES,
    LSTMSequenceClassifier,
    make_paper_baseline,
    paper_baselines,
)

__all__ = [
    "LSTMSequenceClassifier",
    "PAPER_BASELINES",
    "make_paper_baseline",
    "paper_baselines",
]
