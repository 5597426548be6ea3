"""The baselines a practitioner would try first on labelled traces, beside the paper's networks.

Two scikit-learn classifiers of variable-length sequences (a list of ``(T_i, n_features)``
arrays or DataFrames, the propositions of a mission over time), fitted on one or several
binary objectives at once:

- :class:`TemporalLogisticRegression`: a logistic regression on five plain temporal features
  of every proposition (:func:`temporal_features`), in a :class:`~sklearn.pipeline.Pipeline`
  that drops duplicated features and standardises, with the regularisation strength chosen by
  an inner stratified cross-validation on the training set only.
- :class:`MiniRocketClassifier`: MiniRocket (Dempster, Schmidt and Webb, "MiniRocket: a very
  fast (almost) deterministic transform for time series classification", KDD 2021) in the
  multivariate, unequal-length form of sktime's ``MiniRocketMultivariateVariable``
  (:mod:`baselines._minirocket`, numpy and numba), followed by a standardisation and
  :class:`~sklearn.linear_model.RidgeClassifierCV` (its regularisation chosen by
  leave-one-out on the training set), as in the paper.

Neither imports torch nor needs any package beyond the classifier's own (scikit-learn, numba).
Both are deterministic given ``random_state``.
"""

from __future__ import annotations

from numbers import Integral

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin, TransformerMixin
from sklearn.linear_model import LogisticRegression, RidgeClassifierCV
from sklearn.model_selection import GridSearchCV, StratifiedKFold
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from sklearn.utils import check_random_state
from sklearn.utils.metaestimators import available_if
from sklearn.utils.validation import check_is_fitted
from threadpoolctl import threadpool_limits

from baselines._minirocket import fit_minirocket, transform_minirocket
from baselines._sequences import check_consistent_sequences, check_sequences

__all__ = [
    "PRACTITIONER_BASELINES",
    "TEMPORAL_FEATURES",
    "DropDuplicateColumns",
    "MiniRocketClassifier",
    "TemporalLogisticRegression",
    "make_practitioner_baseline",
    "temporal_features",
]

#: The five features of every proposition, in column order (see :func:`temporal_features`).
TEMPORAL_FEATURES = ("first", "last", "fraction_true", "first_true_step", "last_false_step")

#: The practitioner's rows of ``bsi-lfe compare`` and ``bsi-lfe study``, in display order.
PRACTITIONER_BASELINES = ("Logistic regression", "MiniRocket")

#: Inverse regularisation strengths tried by :class:`TemporalLogisticRegression`.
LOGISTIC_CS = tuple(float(c) for c in np.logspace(-3, 3, 13))
#: Ridge penalties tried by :class:`MiniRocketClassifier` (Dempster et al.'s grid).
RIDGE_ALPHAS = tuple(float(a) for a in np.logspace(-3, 3, 10))


def temporal_features(X):
    """Five plain features of every column of every sequence.

    For each feature (proposition) ``p`` of a sequence of ``T`` steps, a value counting as
    true when it is non-zero:

    - ``first``: its value at the first step;
    - ``last``: its value at the last step;
    - ``fraction_true``: the fraction of steps at which it is true;
    - ``first_true_step``: the first step (from 0) at which it is true, ``T`` when never;
    - ``last_false_step``: the last step at which it is false, ``-1`` when never.

    These are not independent: for a proposition that turns true once and stays true,
    ``last_false_step == first_true_step - 1`` on every sequence; one that starts with the
    same value in every mission has a constant ``first`` (and ``first_true_step`` 0 when it
    starts true); one that never changes within a mission (a briefing condition) has
    ``last == fraction_true == first``. :class:`DropDuplicateColumns` removes such columns on
    the training set: on the 272 missions of a default study repeat, 30 of the paper set's 55
    columns remain, and 48 of the extended set's 95.

    Parameters
    ----------
    X : list of array-like or DataFrame
        Sequences ``(T_i, n_features)`` (the formats of :class:`baselines.LSTMSequenceClassifier`).

    Returns
    -------
    features : ndarray of shape (n_sequences, 5 * n_features)
        Column ``5 * p + k`` is feature ``TEMPORAL_FEATURES[k]`` of column ``p``.

    Examples
    --------
    >>> import numpy as np
    >>> from baselines.practitioner import temporal_features
    >>> temporal_features([np.array([[0, 1], [1, 1], [1, 0]])]).tolist()
    [[0.0, 1.0, 0.6666666666666666, 1.0, 0.0, 1.0, 0.0, 0.6666666666666666, 0.0, 2.0]]
    """
    return _temporal_features(check_sequences(X, estimator_name="temporal_features"))


def _temporal_features(sequences):
    n, p = sequences.n_sequences, sequences.n_features
    out = np.empty((n, p, len(TEMPORAL_FEATURES)))
    for i in range(n):
        x = sequences.sequence(i)
        true = x != 0
        t = len(x)
        out[i, :, 0] = x[0]
        out[i, :, 1] = x[-1]
        out[i, :, 2] = true.mean(axis=0)
        out[i, :, 3] = np.where(true.any(axis=0), true.argmax(axis=0), t)
        out[i, :, 4] = np.where((~true).any(axis=0), t - 1 - (~true)[::-1].argmax(axis=0), -1)
    return out.reshape(n, p * len(TEMPORAL_FEATURES))


def _feature_names(sequences):
    names = (sequences.feature_names if sequences.feature_names is not None
             else [f"x{j}" for j in range(sequences.n_features)])
    return np.array([f"{name}:{kind}" for name in names for kind in TEMPORAL_FEATURES],
                    dtype=object)


class DropDuplicateColumns(TransformerMixin, BaseEstimator):
    """Drop constant columns and columns that are an affine function of an earlier column.

    Found on the data given to ``fit`` (the training set): a column is dropped when it is
    constant, or when its absolute Pearson correlation with an earlier kept column is 1 (up to
    ``tol``), i.e. it carries nothing that column does not. A linear model then does not
    split one feature's weight over copies of it, which would weaken its regularisation.

    Parameters
    ----------
    tol : float, default=1e-9

    Attributes
    ----------
    keep_ : ndarray of int
        Positions of the kept columns.
    n_features_in_ : int
    """

    def __init__(self, tol=1e-9):
        self.tol = tol

    def fit(self, X, y=None):
        """Find the columns to keep on ``X``."""
        X = np.asarray(X, dtype=float)
        self.n_features_in_ = X.shape[1]
        centred = X - X.mean(axis=0)
        norms = np.sqrt((centred ** 2).sum(axis=0))
        scale = np.maximum(np.abs(X).max(axis=0), 1.0)
        varying = norms > self.tol * scale * np.sqrt(len(X))
        units = np.zeros_like(centred)
        units[:, varying] = centred[:, varying] / norms[varying]
        duplicate = np.abs(units.T @ units) >= 1 - self.tol  # |correlation| = 1
        keep = []
        for j in np.flatnonzero(varying):
            if not duplicate[j, keep].any():
                keep.append(int(j))
        if not keep:  # every column constant: keep one, the model then predicts its prior
            keep = [0]
        self.keep_ = np.array(keep, dtype=np.int64)
        return self

    def transform(self, X):
        """Keep the columns found by ``fit``."""
        check_is_fitted(self)
        return np.asarray(X, dtype=float)[:, self.keep_]


class _MultiObjective(ClassifierMixin, BaseEstimator):
    """One binary model per objective on shared features; a single-class objective is constant.

    Subclasses define ``_features(sequences, fit, seed)`` and ``_fit_one(F, y, seed)``, and
    set ``_probabilistic`` when the models ``_fit_one`` returns have ``predict_proba`` (then
    so does the classifier). Fit and predict run on one BLAS thread, so that the results do
    not depend on how many cores the process has (a worker of ``n_jobs=2`` or a whole
    machine).
    """

    #: Whether the per-objective models give probabilities (``predict_proba`` exists).
    _probabilistic = False

    def fit(self, X, y):
        """Fit on sequences ``X`` and binary labels ``y`` (n,) or (n, n_objectives)."""
        with threadpool_limits(1):
            return self._fit(X, y)

    def _fit(self, X, y):
        sequences = check_sequences(X, estimator_name=type(self).__name__)
        y = np.asarray(y)
        if y.ndim not in (1, 2) or len(y) != sequences.n_sequences:
            raise ValueError(f"y must be 1-D or 2-D with one row per sequence "
                             f"({sequences.n_sequences}), got shape {y.shape}")
        self._multi_output = y.ndim == 2
        Y = y.reshape(len(y), -1)
        self.n_features_in_ = sequences.n_features
        if sequences.feature_names is not None:
            self.feature_names_in_ = sequences.feature_names
        elif hasattr(self, "feature_names_in_"):
            del self.feature_names_in_
        rng = check_random_state(self.random_state)
        # the features' seed first: objective k gets the same seed alone or with others
        feature_seed = int(rng.randint(np.iinfo(np.int32).max))
        seeds = rng.randint(np.iinfo(np.int32).max, size=Y.shape[1])
        F = self._features(sequences, fit=True, seed=feature_seed)
        self.estimators_, classes = [], []
        for k in range(Y.shape[1]):
            values = np.unique(Y[:, k])
            classes.append(values)
            self.estimators_.append(values[0] if len(values) == 1
                                    else self._fit_one(F, Y[:, k], int(seeds[k])))
        self.classes_ = classes if self._multi_output else classes[0]
        return self

    def predict(self, X):
        """Labels ``(n,)``, or ``(n, n_objectives)`` when fitted on 2-D ``y``."""
        with threadpool_limits(1):
            return self._predict(X)

    def _predict(self, X):
        F = self._test_features(X)
        columns = [est.predict(F) if hasattr(est, "predict") else np.full(len(F), est)
                   for est in self.estimators_]
        pred = np.column_stack(columns)
        return pred if self._multi_output else pred[:, 0]

    @available_if(lambda self: self._probabilistic)
    def predict_proba(self, X):
        """Probability of each label of each objective.

        Parameters
        ----------
        X : list of array-like or DataFrame
            Sequences with the features seen in ``fit``.

        Returns
        -------
        proba : ndarray of shape (n_sequences, n_classes) or list of such arrays
            For 1-D ``y`` in ``fit``, one array whose columns follow ``classes_``; for 2-D
            ``y``, a list with one array per objective, columns following ``classes_[k]``
            (as :class:`baselines.LSTMSequenceClassifier`). An objective seen with a single
            label has a single column of ones.
        """
        with threadpool_limits(1):
            F = self._test_features(X)
            out = [est.predict_proba(F) if hasattr(est, "predict_proba")
                   else np.ones((len(F), 1)) for est in self.estimators_]
        return out if self._multi_output else out[0]

    def _test_features(self, X):
        check_is_fitted(self, "estimators_")
        sequences = check_sequences(X, estimator_name=type(self).__name__)
        check_consistent_sequences(sequences, self.n_features_in_,
                                   getattr(self, "feature_names_in_", None),
                                   type(self).__name__)
        return self._features(sequences, fit=False, seed=None)


class TemporalLogisticRegression(_MultiObjective):
    """Logistic regression on :func:`temporal_features`, regularisation by inner CV.

    The pipeline is ``DropDuplicateColumns -> StandardScaler -> LogisticRegression`` (L2,
    lbfgs). Its ``C`` is chosen among ``Cs`` by a stratified, shuffled ``k``-fold
    cross-validation on the training set only (``k = min(max_folds, smallest class count)``,
    scored by log-loss, which separates values of ``C`` that tie on accuracy on a few
    missions), then the pipeline is refitted on every training sequence. With one sequence of
    a class there is nothing to cross-validate: ``C = 1``. An objective with one class in the
    training set is predicted constant. ``predict_proba`` gives the pipelines' probabilities
    (the scores of ``bsi-lfe compare`` and ``study`` read them for the log loss).

    Parameters
    ----------
    Cs : sequence of float, default=13 values from 1e-3 to 1e3, log-spaced
    max_folds : int, default=3
        Folds of the inner cross-validation (as the study's BSI GridSearchCV).
    random_state : int, RandomState or None, default=None
        Shuffles the inner folds.

    Attributes
    ----------
    estimators_ : list
        Per objective, the fitted pipeline (a ``GridSearchCV``'s best) or the constant label.
    chosen_C_ : list of float or None
        Per objective, the ``C`` used (``None`` for a constant objective).
    classes_ : ndarray or list of ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from baselines.practitioner import TemporalLogisticRegression
    >>> X = [np.array([[0], [1], [1]]), np.array([[0], [0], [0]])] * 4
    >>> y = np.array([1, 0] * 4)
    >>> TemporalLogisticRegression(random_state=0).fit(X, y).predict(X[:2]).tolist()
    [1, 0]
    """

    _probabilistic = True

    def __init__(self, *, Cs=LOGISTIC_CS, max_folds=3, random_state=None):
        self.Cs = Cs
        self.max_folds = max_folds
        self.random_state = random_state

    def fit(self, X, y):
        """Fit one pipeline per objective (see the class docstring)."""
        if isinstance(self.max_folds, bool) or not isinstance(self.max_folds, Integral) \
                or self.max_folds < 2:
            raise ValueError(f"max_folds must be an integer >= 2, got {self.max_folds!r}")
        super().fit(X, y)
        self.chosen_C_ = [float(est[-1].C) if hasattr(est, "predict") else None
                          for est in self.estimators_]
        return self

    def _features(self, sequences, fit, seed):
        return _temporal_features(sequences)

    def _fit_one(self, F, y, seed):
        pipe = make_pipeline(DropDuplicateColumns(), StandardScaler(),
                             LogisticRegression(C=1.0, max_iter=10_000))
        n_min = int(np.unique(y, return_counts=True)[1].min())
        if n_min < 2:
            return pipe.fit(F, y)
        cv = StratifiedKFold(min(int(self.max_folds), n_min), shuffle=True, random_state=seed)
        search = GridSearchCV(pipe, {"logisticregression__C": list(self.Cs)},
                              scoring="neg_log_loss", cv=cv, n_jobs=1, error_score="raise")
        search.fit(F, y)
        return search.best_estimator_


class MiniRocketClassifier(_MultiObjective):
    """MiniRocket features, standardised, then a ridge classifier per objective.

    The transform (:func:`baselines._minirocket.fit_minirocket`: about ``num_kernels`` PPV
    features from the fixed 84 kernels of length 9, dilations up to the longest training
    sequence, biases from quantiles of the convolution outputs of training sequences, random
    channel combinations) is fitted on the training sequences only. Each objective gets a
    :class:`~sklearn.linear_model.RidgeClassifierCV` over ``alphas`` (efficient leave-one-out
    on the training set), as Dempster et al. do; an objective with one class in the training
    set is predicted constant. Every sequence needs at least 9 steps.

    Parameters
    ----------
    num_kernels : int, default=10_000
    alphas : sequence of float, default=10 values from 1e-3 to 1e3, log-spaced
    random_state : int, RandomState or None, default=None
        Seeds the transform (channel combinations and the sequences its biases come from).
    max_dilations_per_kernel : int, default=32

    Attributes
    ----------
    transform_ : MiniRocketParameters
        The fitted transform.
    scaler_ : StandardScaler
    estimators_ : list
        Per objective, the fitted ``RidgeClassifierCV`` or the constant label.
    classes_ : ndarray or list of ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from baselines.practitioner import MiniRocketClassifier
    >>> X = [np.repeat([[0], [1]], [t, 12 - t], axis=0) for t in (2, 3, 9, 10)] * 3
    >>> y = np.array([1, 1, 0, 0] * 3)
    >>> MiniRocketClassifier(num_kernels=84, random_state=0).fit(X, y).predict(X[:4]).tolist()
    [1, 1, 0, 0]
    """

    def __init__(self, *, num_kernels=10_000, alphas=RIDGE_ALPHAS, random_state=None,
                 max_dilations_per_kernel=32):
        self.num_kernels = num_kernels
        self.alphas = alphas
        self.random_state = random_state
        self.max_dilations_per_kernel = max_dilations_per_kernel

    def _features(self, sequences, fit, seed):
        if fit:
            self.transform_ = fit_minirocket(
                sequences.data, sequences.offsets, num_features=int(self.num_kernels),
                max_dilations_per_kernel=int(self.max_dilations_per_kernel), seed=seed)
        F = transform_minirocket(sequences.data, sequences.offsets, self.transform_)
        if fit:
            self.scaler_ = StandardScaler().fit(F)
        return self.scaler_.transform(F)

    def _fit_one(self, F, y, seed):
        return RidgeClassifierCV(alphas=list(self.alphas)).fit(F, y)


def make_practitioner_baseline(name, *, random_state=None):
    """One of :data:`PRACTITIONER_BASELINES` by name, with the defaults above."""
    if name == "Logistic regression":
        return TemporalLogisticRegression(random_state=random_state)
    if name == "MiniRocket":
        return MiniRocketClassifier(random_state=random_state)
    raise ValueError(f"unknown practitioner baseline {name!r}; choose among "
                     f"{list(PRACTITIONER_BASELINES)}")
