"""Baselines of the large-force-exercise comparison: the paper's networks and a practitioner's.

The paper's recurrent networks (:class:`LSTMSequenceClassifier`: LSTM, Bi-LSTM, standalone
or phase-coupled, in ``lstm``) and the classifiers a practitioner would try first on labelled
traces (:class:`TemporalLogisticRegression`, :class:`MiniRocketClassifier`, in
``practitioner``; no torch, ``PRACTITIONER_BASELINES`` and :func:`make_practitioner_baseline`
name them). Both kinds are imported on first use, so that ``PAPER_BASELINES`` (and the
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
    "MiniRocketClassifier",
    "PRACTITIONER_BASELINES",
    "TemporalLogisticRegression",
    "make_practitioner_baseline",
    "temporal_features",
    "PAPER_BASELINES",
    "make_paper_baseline",
    "paper_baselines",
    "require_torch",
]

_TORCH_NAMES = {"LSTMSequenceClassifier", "make_paper_baseline", "paper_baselines"}
_PRACTITIONER_NAMES = {"MiniRocketClassifier", "PRACTITIONER_BASELINES",
                       "TemporalLogisticRegression", "make_practitioner_baseline",
                       "temporal_features"}


def __getattr__(name):
    if name in _TORCH_NAMES:
        return getattr(importlib.import_module("baselines.lstm"), name)
    if name in _PRACTITIONER_NAMES:
        return getattr(importlib.import_module("baselines.practitioner"), name)
    raise AttributeError(f"module 'baselines' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | _TORCH_NAMES | _PRACTITIONER_NAMES)
