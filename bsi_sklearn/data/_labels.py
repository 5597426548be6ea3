"""Labels of demonstrations: ``check_labels`` (re-exported by :mod:`bsi_sklearn.data.traces`)."""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["check_labels"]


def check_labels(y, n_demos, pos_label=None):
    """Validate labels; return ``(y01, classes)`` with ``y01`` in {0, 1}.

    ``y=None`` means every demonstration is acceptable (positive-only learning).

    Parameters
    ----------
    y : array-like of shape (n_demos,) or None
        Labels: 0/1 or booleans, or any two values with ``pos_label`` naming the acceptable
        one.
    n_demos : int
        Number of demonstrations.
    pos_label : object, default=None
        The acceptable label.

    Returns
    -------
    y01 : ndarray of shape (n_demos,), dtype int8
        1 for acceptable demonstrations, 0 for unacceptable ones.
    classes : ndarray of shape (2,)
        The unacceptable then the acceptable label.

    Examples
    --------
    >>> y01, classes = check_labels(["no", "yes", "yes"], 3, pos_label="yes")
    >>> y01.tolist(), classes.tolist()
    ([0, 1, 1], ['no', 'yes'])
    """
    if y is None:
        return np.ones(n_demos, dtype=np.int8), np.array([0, 1])
    y_arr = np.asarray(y)
    if y_arr.ndim == 2 and y_arr.shape[1] == 1:
        warnings.warn(
            "A column-vector y was passed when a 1d array was expected; it is raveled.",
            _data_conversion_warning(),
            stacklevel=3,
        )
        y_arr = y_arr.ravel()
    if y_arr.ndim != 1:
        raise ValueError(f"y must be 1-D (one label per demonstration), got shape {y_arr.shape}")
    if y_arr.shape[0] != n_demos:
        raise ValueError(
            f"y has {y_arr.shape[0]} labels but there are {n_demos} demonstrations"
        )
    if y_arr.dtype.kind == "f" and not np.isfinite(y_arr).all():
        raise ValueError(
            f"y has a NaN or infinite label at demonstration {int(np.argmin(np.isfinite(y_arr)))}"
        )
    values = np.unique(y_arr)
    if y_arr.dtype.kind == "f" and np.any(values != np.round(values)):
        raise ValueError(
            "Unknown label type: continuous. BSIClassifier expects binary labels "
            "(acceptable = 1, unacceptable = 0)"
        )
    if len(values) > 2:
        raise ValueError(
            "Only binary classification is supported. The type of the target is multiclass: "
            f"y has {len(values)} classes {values.tolist()[:10]}, while BSI separates "
            "acceptable from unacceptable demonstrations"
        )
    if pos_label is not None:
        if pos_label not in values.tolist():
            if len(values) == 2:
                raise ValueError(
                    f"pos_label={pos_label!r} is not among the labels {values.tolist()}"
                )
            raise ValueError(
                f"y has the single label {values[0]!r}, which is not pos_label={pos_label!r}; "
                "at least one acceptable demonstration is required"
            )
        y01 = (y_arr == pos_label).astype(np.int8)
        if len(values) == 2:
            classes = values
            if classes[1] != pos_label:
                classes = classes[::-1].copy()
        else:
            classes = np.array([None, pos_label], dtype=object)
        return y01, classes
    if y_arr.dtype == bool:
        return y_arr.astype(np.int8), np.array([False, True])
    if not set(values.tolist()) <= {0, 1}:
        raise ValueError(
            f"labels must be 0/1 (or booleans); got {values.tolist()}. Pass pos_label to name "
            "the acceptable label"
        )
    y01 = y_arr.astype(np.int8)
    if not y01.any():
        raise ValueError(
            "y has only unacceptable (0) demonstrations; BSI needs at least one acceptable (1) "
            "demonstration"
        )
    return y01, np.array([0, 1], dtype=y_arr.dtype if y_arr.dtype.kind in "iu" else int)


def _data_conversion_warning():
    from sklearn.exceptions import DataConversionWarning

    return DataConversionWarning
