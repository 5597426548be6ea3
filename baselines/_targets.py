"""The labels of the LSTM baselines: binary objectives, loss weights, the validation split."""

from __future__ import annotations

import math
import warnings

import numpy as np
from sklearn.exceptions import DataConversionWarning
from sklearn.model_selection import train_test_split
from sklearn.utils import assert_all_finite
from sklearn.utils.class_weight import compute_class_weight
from sklearn.utils.multiclass import type_of_target

__all__ = ["check_targets", "label_weights", "split_indices"]


def check_targets(y, n_sequences, estimator_name):
    """Return ``(y01, classes, multi_output)``; ``y01`` is ``(n, n_outputs)`` float32.

    ``classes`` holds the sorted labels of every objective (one or two each); a column vector
    ``y`` warns as scikit-learn does and is read as 1-D.
    """
    if y is None:
        raise ValueError(
            f"{estimator_name} requires y to be passed, but the target y is None"
        )
    y_arr = np.asarray(y)
    multi = y_arr.ndim == 2
    if y_arr.ndim == 2 and y_arr.shape[1] == 1:
        warnings.warn(
            "A column-vector y was passed when a 1d array was expected. Please change the "
            "shape of y to (n_samples,), for example using ravel().",
            DataConversionWarning,
            stacklevel=3,
        )
        y_arr, multi = y_arr.ravel(), False
    if y_arr.ndim == 1:
        y_arr = y_arr[:, None]
    if y_arr.ndim != 2:
        raise ValueError(f"y must be 1-D or 2-D, got shape {np.asarray(y).shape}")
    if y_arr.shape[0] != n_sequences:
        raise ValueError(
            f"Found input variables with inconsistent numbers of samples: "
            f"[{n_sequences}, {y_arr.shape[0]}] (sequences, labels)"
        )
    if y_arr.shape[1] == 0:
        raise ValueError("y has no columns; at least one objective is required")
    y01 = np.zeros(y_arr.shape, dtype=np.float32)
    classes = []
    for k in range(y_arr.shape[1]):
        col = y_arr[:, k]
        where = f"objective {k} of y" if multi else "y"
        # before type_of_target, which would cast NaN or infinity to int on the way
        assert_all_finite(col, input_name=where)
        kind = type_of_target(col, input_name="y")
        if kind not in ("binary", "multiclass"):
            raise ValueError(f"Unknown label type: {kind} in {where}; labels must be binary")
        values = np.unique(col)
        if len(values) > 2:
            raise ValueError(
                "Only binary classification is supported. The type of the target is "
                f"multiclass: {where} has {len(values)} classes {values.tolist()[:10]}; "
                f"{estimator_name} needs two labels per objective"
            )
        classes.append(values)
        y01[:, k] = np.searchsorted(values, col)
    return y01, classes, multi


def split_indices(y01, validation_fraction, seed):
    """Split the sequences into sorted training and validation indices.

    Stratified on the label combination where every combination has two members or more,
    else on the first objective, else at random; no validation set without a fraction or with
    fewer than two sequences.
    """
    n = y01.shape[0]
    all_idx = np.arange(n)
    if not validation_fraction or n < 2:
        return all_idx, np.empty(0, dtype=np.int64)
    n_valid = min(max(1, math.ceil(validation_fraction * n)), n - 1)
    _, combos = np.unique(y01, axis=0, return_inverse=True)
    for stratify in (combos.ravel(), y01[:, 0], None):
        try:
            train, valid = train_test_split(
                all_idx, test_size=n_valid, random_state=seed, stratify=stratify
            )
        except ValueError:
            continue
        return np.sort(train), np.sort(valid)
    raise AssertionError("unstratified split cannot fail")  # pragma: no cover


def label_weights(y01, classes, class_weight):
    """Weight ``(n, n_outputs)`` of every sequence's label in each objective's loss."""
    cw = class_weight
    weights = np.ones(y01.shape, dtype=np.float32)
    if cw is None:
        return weights
    if isinstance(cw, dict):
        if len(classes) > 1:
            raise ValueError(
                "class_weight must be a list of dicts, one per objective, when y has "
                f"{len(classes)} columns, or 'balanced'"
            )
        cw = [cw]
    elif not isinstance(cw, str) and len(cw) != len(classes):
        raise ValueError(
            f"class_weight has {len(cw)} dicts but y has {len(classes)} objectives"
        )
    for k, values in enumerate(classes):
        spec = cw if isinstance(cw, str) else cw[k]
        labels = values[y01[:, k].astype(np.int64)]
        per_class = compute_class_weight(spec, classes=values, y=labels)
        weights[:, k] = per_class[y01[:, k].astype(np.int64)]
    return weights
