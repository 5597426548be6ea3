"""Recurrent baselines of the paper's large-force-exercise comparison (LSTM, Bi-LSTM, coupled).

The torch-backed names are imported on first use, so that ``PAPER_BASELINES`` (and the
``bsi-lfe`` command line that lists it) does not load torch. torch is the optional extra
``bsi-sklearn[baselines]``: without it those names raise ``ModuleNotFoundError`` saying
``pip install "bsi-sklearn[baselines]"`` (:func:`require_torch` checks up front).
"""

import importlib

from baselines._paper import FAIR_TRAINING, PAPER_BASELINES
from baselines._torch import require_torch

__all__ = [
    "FAIR_TRAINING",
    "LSTMSequenceClassifier",
    "PAPER_BASELINES",
    "make_paper_baseline",
    "paper_baselines",
    "require_torch",
]

_TORCH_NAMES = {"LSTMSequenceClassifier", "make_paper_baseline", "paper_baselines"}


def __getattr__(name):
    if name in _TORCH_NAMES:
        return getattr(importlib.import_module("baselines.lstm"), name)
    raise AttributeError(f"module 'baselines' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | _TORCH_NAMES)
