"""Negated propositions: a transformer appending ``!p`` for chosen propositions ``p``."""

from __future__ import annotations

from numbers import Real

import numpy as np
import pandas as pd
from sklearn.base import BaseEstimator, TransformerMixin
from sklearn.utils.validation import check_is_fitted

from bsi_sklearn.data.roles import resolve_propositions
from bsi_sklearn.data.traces import check_consistent_traces, check_traces, is_frame
from bsi_sklearn.param_validation import Satisfies, validate_params

__all__ = ["NegationAugmenter", "add_negations"]


class NegationAugmenter(TransformerMixin, BaseEstimator, auto_wrap_output_keys=None):
    """Append the negation ``!p`` of propositions ``p`` as new columns of every trace.

    The BSI template only has positive clauses ``G(p)``, ``F(w)`` and ``(!b U a)``. With the
    negations as propositions, absence patterns ``G(!p)``, ``F(!p)`` and orders on
    negations come within reach, e.g. in a pipeline
    ``make_pipeline(NegationAugmenter(), BSIClassifier())``.

    Parameters
    ----------
    propositions : list of str or int, default=None
        Propositions to negate, by name or column index; ``None`` negates all of them.
        The new columns come after the original ones, in this order.
    prefix : str, default="!"
        The name of the negation of ``p`` is ``prefix + p``. The default ``"!"`` makes
        :meth:`Specification.to_ltl` print ``G(!p)``, which reads (and re-parses with
        :func:`bsi_sklearn.ltl.parse_ltl`) as the intended formula, and it is the name
        :meth:`bsi_sklearn.ltl.Formula.to_specification` gives negated literals. Use e.g.
        ``"not_"`` when names must be identifiers.
    binarize : float, default=None
        As in :class:`~bsi_sklearn.BSIClassifier`: values ``> binarize`` are true; by
        default values must be 0/1 or boolean.

    Attributes
    ----------
    n_features_in_ : int
        Number of propositions seen in fit.
    feature_names_in_ : ndarray of str
        Proposition names seen in fit (only when the traces had string column names).
    negated_ : ndarray of int
        Column indices of the negated propositions.
    negations_ : dict
        Each new column -> the column it negates, as a :class:`~bsi_sklearn.Specification`
        names them (``{"!b": "b"}``; for unnamed input the column indices,
        ``{n_features_in_ + k: i}``): the ``negations`` argument of
        :meth:`Specification.readable` and the other renderings, which then write ``!b`` (or
        ``b`` for an order on it, never ``!!b``) whatever the prefix.

    See Also
    --------
    add_negations : Function form.

    Notes
    -----
    The output mirrors the input: a list of traces stays a list (of DataFrames when the
    propositions have names, else of boolean arrays), a 3-D array stays a 3-D array, a
    2-D array of length-one traces (or a single DataFrame) stays 2-D. Values are boolean.
    Column names of unnamed input follow scikit-learn's ``x0, x1, ...`` in
    :meth:`get_feature_names_out` (so the negation of column 0 is ``"!x0"``), and a
    :class:`~bsi_sklearn.Specification` learnt on unnamed augmented arrays refers to the
    negation of column ``i`` by the index ``n_features_in_ + k`` of its new column.

    Examples
    --------
    >>> import pandas as pd
    >>> trace = pd.DataFrame({"a": [1, 0], "b": [0, 0]})
    >>> aug = NegationAugmenter(propositions=["b"])
    >>> [out] = aug.fit_transform([trace])
    >>> out
           a      b     !b
    0   True  False   True
    1  False  False   True
    >>> aug.get_feature_names_out().tolist()
    ['a', 'b', '!b']
    >>> aug.negations_
    {'!b': 'b'}
    """

    # propositions are resolved against the data in fit.
    _parameter_constraints = {
        "propositions": "no_validation",
        "prefix": [Satisfies(lambda v: isinstance(v, str) and v != "", "a non-empty string")],
        "binarize": [None, Real],
    }

    def __init__(self, *, propositions=None, prefix="!", binarize=None):
        self.propositions = propositions
        self.prefix = prefix
        self.binarize = binarize

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.three_d_array = True
        tags.input_tags.two_d_array = True
        return tags

    def fit(self, X, y=None):
        """Check the traces and resolve the propositions to negate.

        Parameters
        ----------
        X : demonstrations
            Any format accepted by :func:`bsi_sklearn.data.traces.check_traces`.
        y : ignored

        Returns
        -------
        self : NegationAugmenter
        """
        validate_params(self.get_params(deep=False), self._parameter_constraints,
                        type(self).__name__)
        traces = check_traces(X, binarize=self.binarize, estimator_name=type(self).__name__,
                              frame_as_rows=True)
        names = traces.feature_names
        self.n_features_in_ = traces.n_props
        if names is not None:
            self.feature_names_in_ = np.asarray(names, dtype=object)
        elif hasattr(self, "feature_names_in_"):
            del self.feature_names_in_
        known = list(names) if names is not None else list(range(traces.n_props))
        self.negated_ = resolve_propositions(self.propositions, known, "propositions")
        out = self.get_feature_names_out()
        seen = set()
        for name in out:
            if name in seen:
                raise ValueError(
                    f"the negation column {name!r} already exists; choose another prefix"
                )
            seen.add(name)
        if names is not None:
            self.negations_ = {str(n): str(names[i])
                               for n, i in zip(out[self.n_features_in_:], self.negated_)}
        else:
            self.negations_ = {self.n_features_in_ + k: int(i)
                               for k, i in enumerate(self.negated_)}
        return self

    def get_feature_names_out(self, input_features=None):
        """Names of the output columns: the input names, then ``prefix + name``.

        Parameters
        ----------
        input_features : array-like of str, default=None
            Input names; default ``feature_names_in_``, else ``x0, x1, ...``.

        Returns
        -------
        names : ndarray of str
        """
        check_is_fitted(self, "negated_")
        if input_features is None:
            input_features = getattr(self, "feature_names_in_", None)
        if input_features is None:
            input_features = [f"x{i}" for i in range(self.n_features_in_)]
        input_features = [str(n) for n in input_features]
        if len(input_features) != self.n_features_in_:
            raise ValueError(
                f"input_features has {len(input_features)} names, expected "
                f"{self.n_features_in_}"
            )
        negated = [self.prefix + input_features[i] for i in self.negated_]
        return np.asarray(input_features + negated, dtype=object)

    def transform(self, X):
        """Append the negated columns.

        Parameters
        ----------
        X : demonstrations
            Any format accepted by :func:`bsi_sklearn.data.traces.check_traces`, with the
            propositions seen in fit.

        Returns
        -------
        X_out : same container as ``X``
            See Notes.
        """
        check_is_fitted(self, "negated_")
        traces = check_traces(X, binarize=self.binarize, estimator_name=type(self).__name__,
                              frame_as_rows=True)
        check_consistent_traces(traces, self.n_features_in_,
                                getattr(self, "feature_names_in_", None), type(self).__name__)
        data = traces.data.astype(bool)
        out = np.concatenate([data, ~data[:, self.negated_]], axis=1)
        named = traces.feature_names is not None
        columns = self.get_feature_names_out(traces.feature_names) if named else None
        if is_frame(X):
            return pd.DataFrame(out, columns=columns, index=X.index)
        if isinstance(X, (list, tuple)):
            items = list(X)
            if not is_frame(items[0]) and np.ndim(items[0]) == 1:
                return out  # nested lists of scalars: the 2-D format
        else:
            arr = np.asarray(X)
            if arr.ndim == 3:
                return out.reshape(traces.n_demos, -1, out.shape[1])
            if arr.ndim == 2 and arr.dtype != object:
                return out
            items = list(arr)  # an object array of traces
        pieces = np.split(out, traces.offsets[1:-1])
        if named:
            cols = pd.Index(list(columns))
            return [pd.DataFrame(p, columns=cols, index=x.index if is_frame(x) else None)
                    for p, x in zip(pieces, items)]
        return pieces


def add_negations(X, propositions=None, *, prefix="!"):
    """Append ``prefix + p`` = not ``p`` for the chosen propositions of every trace.

    Function form of :class:`NegationAugmenter` (fit and transform on ``X``).

    Parameters
    ----------
    X : demonstrations
        Any format accepted by :func:`bsi_sklearn.data.traces.check_traces`.
    propositions : list of str or int, default=None
        Propositions to negate; all by default.
    prefix : str, default="!"
        Name prefix of the negated columns.

    Returns
    -------
    X_out : same container as ``X``

    Examples
    --------
    >>> import numpy as np
    >>> add_negations(np.array([[[1, 0], [0, 0]]]), propositions=[1]).astype(int)
    array([[[1, 0, 1],
            [0, 0, 1]]])
    """
    return NegationAugmenter(propositions=propositions, prefix=prefix).fit_transform(X)
