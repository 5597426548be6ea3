"""LSTM and Bi-LSTM sequence classifiers (standalone and phase-coupled), scikit-learn style.

The estimator: its parameters, ``fit``, its prediction methods and pickling. Its network and
batches are in ``baselines._network``, its training loop in ``baselines._training``, its
labels in ``baselines._targets`` and torch's settings while it runs in ``baselines._runtime``.
"""

from __future__ import annotations

import math
import time
from numbers import Integral, Real

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.utils import check_random_state
from sklearn.utils.validation import check_is_fitted

from baselines._network import Batches, RecurrentNet, predict_batches
from baselines._paper import PAPER_BASELINES
from baselines._runtime import isolated_torch, torch, torch_threads
from baselines._sequences import check_consistent_sequences, check_phases, check_sequences
from baselines._targets import check_targets, label_weights, split_indices
from baselines._training import Training, train
from bsi_sklearn.param_validation import (
    Interval,
    Satisfies,
    StrOptions,
    validate_params,
)

__all__ = [
    "LSTMSequenceClassifier",
    "PAPER_BASELINES",
    "make_paper_baseline",
    "paper_baselines",
]

_POOLINGS = ("last", "mean", "max")
_LIST_OF_DICTS = Satisfies(
    lambda v: isinstance(v, (list, tuple)) and all(isinstance(d, dict) for d in v),
    "a list of dicts",
)


class LSTMSequenceClassifier(ClassifierMixin, BaseEstimator):
    """Recurrent (LSTM or Bi-LSTM) classifier of variable-length sequences.

    The recurrent baselines of the paper's large-force-exercise comparison. A stack of LSTM
    layers reads each sequence; a summary of its outputs (the final hidden state by default)
    feeds one logistic unit per objective, trained with binary cross-entropy, the objectives'
    losses weighted equally. With ``coupled=True`` a second head classifies the scenario phase
    at every time step (categorical cross-entropy over the valid steps), and the total loss is
    the equally weighted sum of the objectives' and the phase losses, as in the paper's
    "Coupled" models.

    Parameters
    ----------
    hidden_size : int, default=32
        Hidden units of each LSTM (per direction).
    num_layers : int, default=1
        Number of stacked LSTM layers.
    bidirectional : bool, default=False
        Read each sequence in both directions (Bi-LSTM). The backward direction runs over each
        sequence reversed inside its own length, so it never reads padding.
    coupled : bool, default=False
        Train a per-time-step phase classifier jointly with the objectives; ``fit`` then
        requires ``phases``.
    n_phases : int, default=4
        Number of phase classes when ``coupled=True`` (the paper's four scenario phases:
        escort push, strikers push, time on target, egress). Ignored otherwise.
    pooling : {"last", "mean", "max"}, default="last"
        Summary of the top layer's outputs given to the objective head: the final hidden state
        (for a Bi-LSTM, the forward state after the last step joined with the backward state
        after the first step), or the mean or maximum over the valid time steps.
    dropout : float, default=0.0
        Dropout on the inputs of every LSTM layer after the first and on the summary.
    max_epochs : int, default=200
        Maximum number of passes over the training sequences.
    lr : float, default=1e-2
        Learning rate of the Adam optimiser.
    batch_size : int, default=32
        Sequences per gradient step (the last batch may be smaller).
    weight_decay : float, default=0.0
        L2 penalty of Adam.
    validation_fraction : float or None, default=0.2
        Fraction of the training sequences held out to monitor the loss for early stopping,
        split stratified on the label combination where every combination has two members or
        more (else on the first objective, else at random). ``None`` or ``0`` (or fewer than
        two sequences) trains on everything and monitors the training loss instead.
    patience : int, default=20
        Stop after this many epochs without improvement of the monitored loss; the weights of
        the best epoch are restored.
    refit : bool, default=False
        After early stopping has chosen the number of epochs on the validation split, train a
        fresh network (same initial weights) on *every* training sequence for exactly that
        many epochs and keep it, so no training sequence is spent on validation only. Without
        a validation split (``validation_fraction`` ``None`` or ``0``, or fewer than two
        sequences) there is nothing to refit and the flag changes nothing. The study and the
        comparison use ``refit=True`` (see :data:`baselines.FAIR_TRAINING`).
    class_weight : dict, list of dict, "balanced" or None, default=None
        Weights of the labels in each objective's binary cross-entropy, as in scikit-learn's
        forests. ``None`` weights every sequence equally (the paper's loss). ``"balanced"``
        weights label ``c`` of objective ``k`` by ``n / (2 * count_k(c))`` over the sequences
        given to ``fit``, so both labels weigh the same in total. A dict ``{label: weight}``
        (1-D ``y``) or a list of such dicts, one per objective (2-D ``y``), sets them by hand.
    standardize : bool, default=True
        Centre and scale every feature with its mean and standard deviation over all training
        time steps (constant features are only centred). Harmless for boolean propositions,
        needed for numeric flight data.
    clip_grad_norm : float or None, default=1.0
        Clip the gradient's global norm to this value; ``None`` disables clipping.
    random_state : int, RandomState instance or None, default=None
        Seeds the weight initialisation, dropout, the validation split and the batch order.
        Torch's global generator is forked inside ``fit`` and restored afterwards, so global
        random state is left untouched.
    verbose : int, default=0
        ``1`` prints a summary per fit, ``2`` one line per epoch.
    device : str, default="cpu"
        Torch device used for training and prediction.
    n_threads : int or None, default=1
        Torch intra-op CPU threads while ``fit`` and the predict methods run; torch's
        setting is restored when they return. ``None`` leaves it alone. One thread is as fast
        as two for these small networks and does not collapse when the cores are shared
        (with two threads on a busy 2-core machine an epoch took 10-15 times longer).

    Attributes
    ----------
    classes_ : ndarray of shape (2,) or list of ndarray
        Labels of each objective: an array for 1-D ``y``, a list of arrays (one per column)
        for 2-D ``y``.
    n_outputs_ : int
        Number of objectives (columns of ``y``; 1 for 1-D ``y``).
    n_features_in_ : int
        Number of features per time step seen in ``fit``.
    feature_names_in_ : ndarray of str
        Feature names seen in ``fit``, when the sequences were DataFrames with string columns.
    module_ : torch.nn.Module
        The trained network (best epoch).
    feature_mean_, feature_scale_ : ndarray of shape (n_features_in_,)
        Standardisation applied to the inputs (zeros and ones when ``standardize=False``).
    history_ : list of dict
        Per epoch: ``epoch``, ``train_loss``, ``valid_loss`` (``nan`` without validation).
    n_epochs_ : int
        Epochs run.
    best_epoch_ : int
        Epoch (1-based) whose weights were kept.
    best_loss_ : float
        Monitored loss at ``best_epoch_``.
    refit_epochs_ : int
        Epochs of the refit on every training sequence (``refit=True``); 0 without a refit,
        when ``module_`` is the early-stopped network itself.
    fit_time_ : float
        Seconds spent in the last ``fit``.

    See Also
    --------
    make_paper_baseline : The paper's four configurations by name.

    Notes
    -----
    *Inputs.* ``X`` is a list of ``(T_i, n_features)`` arrays or DataFrames (rows are time
    steps; the lengths may differ), a 3-D array of equal-length sequences, or a 2-D array
    whose rows are sequences of length one (the layout scikit-learn's estimator checks use).
    Values may be boolean or numeric. A standalone model should be given only the
    propositions; for a coupled model the caller appends the flight-phase features (e.g. one-hot
    aircraft flight phases) as extra columns, as the paper does. ``fit`` only uses ``phases``
    as training targets: prediction needs the same input columns and no phase labels.

    *Outputs.* For 1-D ``y``, ``predict`` returns labels of shape ``(n,)`` and
    ``predict_proba`` an array ``(n, 2)`` whose columns follow ``classes_``. For 2-D ``y`` of
    shape ``(n, n_outputs)`` (e.g. MO1-MO3), ``predict`` returns ``(n, n_outputs)`` and
    ``predict_proba`` a list with one ``(n, 2)`` array per objective, as
    :class:`sklearn.multioutput.MultiOutputClassifier` does. Every objective must be binary;
    an objective with a single label in the training data is predicted constant (its
    ``predict_proba`` array then has one column, as in scikit-learn's trees).

    *Phases and metadata routing.* ``fit(X, y, phases=...)`` takes one 1-D integer array per
    sequence, as long as the sequence, values in ``[0, n_phases)``. Coupled models raise a
    ``ValueError`` without it; standalone models ignore it, so one call can fit all four
    baselines. With ``sklearn.set_config(enable_metadata_routing=True)``, request it with
    ``clf.set_fit_request(phases=True)`` and pass ``params={"phases": phases}`` to
    :func:`~sklearn.model_selection.cross_validate`; it is split with ``X``. scikit-learn's
    router refuses metadata that no estimator requests, so a loop over the four baselines
    that passes ``phases`` to every one requests it on the standalone models too (they
    ignore it). Without routing, ``params`` go straight to ``fit``.

    *Padding.* Sequences of a batch are zero-padded at the end. The forward direction is
    causal and the backward direction reads each sequence reversed inside its length, every
    summary and loss reads only valid steps, so a sequence's prediction does not depend on
    the other sequences of its batch (up to floating-point rounding of about 1e-7). Padded
    batches run on the fused LSTM kernel, about twenty times faster on CPU than packed ones.

    *Reproducibility.* All randomness comes from ``random_state``: torch is seeded inside a
    forked global generator (:func:`torch.random.fork_rng`), which is not thread-safe, so fit
    models in separate processes (joblib's default) rather than threads. CPU LSTM, linear and
    Adam kernels are deterministic, so the same seed gives the same predictions. The torch
    thread count is set only while a method runs (``n_threads``) and then restored.

    *Class imbalance.* The default loss is the paper's unweighted binary cross-entropy; a
    model that collapses to the majority class on small data shows it honestly.
    ``class_weight="balanced"`` is the option to counter imbalance (it also weighs the
    validation loss used for early stopping).

    Examples
    --------
    >>> import numpy as np
    >>> from baselines import LSTMSequenceClassifier
    >>> rng = np.random.default_rng(0)
    >>> X = [rng.integers(0, 2, size=(int(rng.integers(5, 9)), 2)) for _ in range(20)]
    >>> y = np.array([int(x[:, 0].sum() > x[:, 1].sum()) for x in X])
    >>> clf = LSTMSequenceClassifier(hidden_size=8, max_epochs=5, random_state=0).fit(X, y)
    >>> clf.predict(X[:3]).shape, clf.predict_proba(X[:3]).shape
    ((3,), (3, 2))
    """

    def __init__(self, *, hidden_size=32, num_layers=1, bidirectional=False, coupled=False,
                 n_phases=4, pooling="last", dropout=0.0, max_epochs=200, lr=1e-2,
                 batch_size=32, weight_decay=0.0, validation_fraction=0.2, patience=20,
                 refit=False, class_weight=None, standardize=True, clip_grad_norm=1.0,
                 random_state=None, verbose=0, device="cpu", n_threads=1):
        self.hidden_size = hidden_size
        self.num_layers = num_layers
        self.bidirectional = bidirectional
        self.coupled = coupled
        self.n_phases = n_phases
        self.pooling = pooling
        self.dropout = dropout
        self.max_epochs = max_epochs
        self.lr = lr
        self.batch_size = batch_size
        self.weight_decay = weight_decay
        self.validation_fraction = validation_fraction
        self.patience = patience
        self.refit = refit
        self.class_weight = class_weight
        self.standardize = standardize
        self.clip_grad_norm = clip_grad_norm
        self.random_state = random_state
        self.verbose = verbose
        self.device = device
        self.n_threads = n_threads

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.three_d_array = True
        tags.target_tags.multi_output = True
        tags.classifier_tags.multi_class = False
        tags.classifier_tags.multi_label = True
        return tags

    # ------------------------------------------------------------------ fit

    def fit(self, X, y, phases=None):
        """Train the network on labelled sequences.

        Parameters
        ----------
        X : list of array-like or DataFrame, 3-D array or 2-D array
            Sequences ``(T_i, n_features)``, see Notes.
        y : array-like of shape (n_sequences,) or (n_sequences, n_outputs)
            Binary label(s) of every sequence, one column per objective.
        phases : list of array-like of int, default=None
            Phase label of every time step of every sequence (values in
            ``[0, n_phases)``). Required when ``coupled=True``, ignored otherwise.

        Returns
        -------
        self : LSTMSequenceClassifier
            The fitted classifier.
        """
        start = time.perf_counter()
        self._check_hyperparameters()
        with torch_threads(self.n_threads):
            self._fit(X, y, phases)
        self.fit_time_ = time.perf_counter() - start
        if self.verbose:
            print(
                f"[{type(self).__name__}] {self.n_epochs_} epochs, best epoch "
                f"{self.best_epoch_} (loss {self.best_loss_:.4f}), {self.fit_time_:.2f} s"
            )
        return self

    def _fit(self, X, y, phases):
        name = type(self).__name__
        sequences = check_sequences(X, estimator_name=name)
        y01, classes, multi = check_targets(y, sequences.n_sequences, name)
        phase_data = None
        if self.coupled:
            if phases is None:
                raise ValueError(
                    f"{name}(coupled=True) needs the phase labels: call fit(X, y, "
                    "phases=...) with one 1-D integer array per sequence (with metadata "
                    "routing, set_fit_request(phases=True) and pass params={'phases': ...})"
                )
            phase_data = check_phases(phases, sequences.lengths, self.n_phases)

        self.n_features_in_ = sequences.n_features
        if sequences.feature_names is not None:
            self.feature_names_in_ = sequences.feature_names
        elif hasattr(self, "feature_names_in_"):
            del self.feature_names_in_
        self.classes_ = classes if multi else classes[0]
        self.n_outputs_ = len(classes)
        self._multi_output = multi
        self._constant = np.array([len(c) == 1 for c in classes])
        weights = label_weights(y01, classes, self.class_weight)

        if self.standardize:
            mean = sequences.data.mean(axis=0)
            scale = sequences.data.std(axis=0)
            scale[scale <= 1e-12 * np.maximum(1.0, np.abs(mean))] = 1.0
        else:
            mean = np.zeros(sequences.n_features)
            scale = np.ones(sequences.n_features)
        self.feature_mean_, self.feature_scale_ = mean, scale
        data = ((sequences.data - mean) / scale).astype(np.float32)

        rng = check_random_state(self.random_state)
        torch_seed = int(rng.randint(np.iinfo(np.int32).max))
        split_seed = int(rng.randint(np.iinfo(np.int32).max))
        order_rng = np.random.default_rng(int(rng.randint(np.iinfo(np.int32).max)))
        train_idx, valid_idx = split_indices(y01, self.validation_fraction, split_seed)

        device = torch.device(self.device)
        self._net_config = {
            "n_features": sequences.n_features,
            "hidden_size": int(self.hidden_size),
            "num_layers": int(self.num_layers),
            "bidirectional": bool(self.bidirectional),
            "dropout": float(self.dropout),
            "n_outputs": self.n_outputs_,
            "n_phases": int(self.n_phases) if self.coupled else 0,
            "pooling": self.pooling,
        }
        with isolated_torch(device):
            # padded once, for both phases (every batch of either is a slice of these)
            batches = Batches(data, sequences.offsets, y01, weights, phase_data, device)
            torch.manual_seed(torch_seed)
            module = RecurrentNet(**self._net_config).to(device)
            self._train(module, batches, train_idx, valid_idx, order_rng, device)
            self.refit_epochs_ = 0
            if self.refit and len(valid_idx) and self.best_epoch_ > 0:
                # Same initial weights, every training sequence, the chosen number of epochs.
                torch.manual_seed(torch_seed)
                module = RecurrentNet(**self._net_config).to(device)
                self._train(
                    module, batches, np.arange(sequences.n_sequences),
                    np.empty(0, dtype=np.int64), order_rng, device, epochs=self.best_epoch_,
                )
                self.refit_epochs_ = self.best_epoch_

    _parameter_constraints = {
        "hidden_size": [Interval(Integral, 1, None, closed="left")],
        "num_layers": [Interval(Integral, 1, None, closed="left")],
        "bidirectional": ["boolean"],
        "coupled": ["boolean"],
        "n_phases": [Interval(Integral, 2, None, closed="left")],  # checked when coupled
        "pooling": [StrOptions(_POOLINGS)],
        "dropout": [Interval(Real, 0, 1, closed="left")],
        "max_epochs": [Interval(Integral, 1, None, closed="left")],
        "lr": [Interval(Real, 0, math.inf, closed="neither")],
        "batch_size": [Interval(Integral, 1, None, closed="left")],
        "weight_decay": [Interval(Real, 0, math.inf, closed="left")],
        "validation_fraction": [Interval(Real, 0, 1, closed="left"), None],
        "patience": [Interval(Integral, 1, None, closed="left")],
        "class_weight": [None, StrOptions(("balanced",)), dict, _LIST_OF_DICTS],
        "standardize": ["boolean"],
        "refit": ["boolean"],
        "clip_grad_norm": [Interval(Real, 0, math.inf, closed="neither"), None],
        "random_state": "no_validation",  # check_random_state, in fit
        "verbose": "no_validation",
        "device": "no_validation",  # any torch.device spec, checked below
        "n_threads": [Interval(Integral, 1, None, closed="left"), None],
    }

    def _check_hyperparameters(self):
        params = self.get_params(deep=False)
        if not self.coupled:
            params.pop("n_phases", None)
        validate_params(params, self._parameter_constraints, type(self).__name__)
        try:
            torch.device(self.device)
        except (RuntimeError, TypeError) as exc:
            raise ValueError(f"device {self.device!r} is not a torch device: {exc}") from None

    def _train(self, module, batches, train_idx, valid_idx, order_rng, device, epochs=None):
        """Train ``module`` with early stopping, or for exactly ``epochs`` epochs (a refit).

        With ``epochs`` the weights after the last epoch are kept in ``module_`` and the
        early-stopping attributes (``history_``, ``best_epoch_``, ...) are left as they are.
        """
        objective_mask = torch.as_tensor(~self._constant, dtype=torch.float32, device=device)
        settings = Training(lr=self.lr, weight_decay=self.weight_decay,
                            batch_size=self.batch_size, clip_grad_norm=self.clip_grad_norm,
                            max_epochs=self.max_epochs, patience=self.patience,
                            verbose=self.verbose)
        stopping = train(module, batches, train_idx, valid_idx, order_rng, objective_mask,
                         settings, epochs=epochs)
        self.module_ = module
        if stopping is not None:
            self.history_, self.best_epoch_, self.best_loss_ = stopping
            self.n_epochs_ = len(self.history_)

    # --------------------------------------------------------------- pickle

    def _forward_all(self, X):
        """Objective probabilities ``(n, n_outputs)`` and per-step phase logits (or None)."""
        check_is_fitted(self)
        name = type(self).__name__
        sequences = check_sequences(X, estimator_name=name)
        check_consistent_sequences(
            sequences, self.n_features_in_, getattr(self, "feature_names_in_", None), name
        )
        data = ((sequences.data - self.feature_mean_) / self.feature_scale_).astype(np.float32)
        with torch_threads(self.n_threads):
            return predict_batches(self.module_, data, sequences.offsets, sequences.lengths,
                                   self.n_outputs_, step=max(int(self.batch_size), 64))

    def predict_proba(self, X):
        """Probability of each label of each objective.

        Parameters
        ----------
        X : list of array-like or DataFrame, 3-D array or 2-D array
            Sequences with the features seen in ``fit``.

        Returns
        -------
        proba : ndarray of shape (n_sequences, 2) or list of such arrays
            For 1-D ``y`` in ``fit``, one array whose columns follow ``classes_``; for 2-D
            ``y``, a list with one array per objective, columns following ``classes_[k]``. An
            objective seen with a single label has a single column of ones.
        """
        proba, _ = self._forward_all(X)
        out = []
        for k in range(self.n_outputs_):
            if self._constant[k]:
                out.append(np.ones((proba.shape[0], 1)))
            else:
                out.append(np.column_stack([1.0 - proba[:, k], proba[:, k]]))
        return out if self._multi_output else out[0]

    def predict(self, X):
        """Predicted label(s) of every sequence.

        Parameters
        ----------
        X : list of array-like or DataFrame, 3-D array or 2-D array
            Sequences with the features seen in ``fit``.

        Returns
        -------
        y : ndarray of shape (n_sequences,) or (n_sequences, n_outputs)
            The label with probability at least 0.5 per objective (ties go to the second
            class).
        """
        proba, _ = self._forward_all(X)
        classes = self.classes_ if self._multi_output else [self.classes_]
        columns = []
        for k, cls in enumerate(classes):
            if self._constant[k]:
                columns.append(np.repeat(cls[:1], proba.shape[0]))
            else:
                columns.append(cls[(proba[:, k] >= 0.5).astype(np.int64)])
        if not self._multi_output:
            return columns[0]
        dtype = np.result_type(*[c.dtype for c in columns])
        return np.column_stack([c.astype(dtype) for c in columns])

    def predict_phases(self, X):
        """Most probable phase at every time step (coupled models only).

        Parameters
        ----------
        X : list of array-like or DataFrame, 3-D array or 2-D array
            Sequences with the features seen in ``fit``.

        Returns
        -------
        phases : list of ndarray of int
            One array per sequence, as long as the sequence, values in ``[0, n_phases)``.
        """
        check_is_fitted(self)
        if not self._net_config["n_phases"]:
            raise ValueError("predict_phases needs a model fitted with coupled=True")
        _, phase_logits = self._forward_all(X)
        return [p.argmax(axis=1) for p in phase_logits]

    def score(self, X, y, sample_weight=None):
        """Accuracy; for several objectives, the fraction of sequences with all of them right.

        Parameters
        ----------
        X : list of array-like or DataFrame, 3-D array or 2-D array
            Sequences with the features seen in ``fit``.
        y : array-like of shape (n_sequences,) or (n_sequences, n_outputs)
            True labels.
        sample_weight : array-like of shape (n_sequences,), default=None
            Weights of the sequences.

        Returns
        -------
        score : float
            Mean (subset) accuracy, as :class:`~sklearn.multioutput.MultiOutputClassifier`
            computes it.
        """
        y_true = np.asarray(y)
        y_pred = self.predict(X)
        if y_pred.ndim == 1:
            y_true = y_true.ravel() if y_true.ndim == 2 and y_true.shape[1] == 1 else y_true
            return float(np.average(y_true == y_pred, weights=sample_weight))
        if y_true.shape != y_pred.shape:
            raise ValueError(f"y has shape {y_true.shape}, predictions have {y_pred.shape}")
        return float(np.average(np.all(y_true == y_pred, axis=1), weights=sample_weight))

    def __getstate__(self):
        state = dict(super().__getstate__())
        module = state.pop("module_", None)
        if module is not None:
            state["_module_state"] = {
                k: v.detach().cpu().clone() for k, v in module.state_dict().items()
            }
        return state

    def __setstate__(self, state):
        module_state = state.pop("_module_state", None)
        super().__setstate__(state)
        if module_state is not None:
            module = RecurrentNet(**self._net_config)
            module.load_state_dict(module_state)
            module.eval()
            self.module_ = module



def make_paper_baseline(name, **params):
    """One of the paper's four recurrent baselines by name.

    Parameters
    ----------
    name : {"LSTM", "Bi-LSTM", "LSTM Coupled", "Bi-LSTM Coupled"}
        The model as named in the paper's Table of weighted F1 scores.
    **params
        Further :class:`LSTMSequenceClassifier` parameters (``random_state``, ``n_phases``,
        ...); ``bidirectional`` and ``coupled`` are set by ``name``.

    Returns
    -------
    clf : LSTMSequenceClassifier
        Unfitted. Coupled models need ``phases`` in ``fit`` (with metadata routing enabled,
        call ``clf.set_fit_request(phases=True)``) and, as in the paper, their inputs should
        carry the flight-phase features besides the propositions.

    Examples
    --------
    >>> import numpy as np
    >>> from baselines import make_paper_baseline
    >>> clf = make_paper_baseline("Bi-LSTM Coupled", n_phases=2, max_epochs=3, random_state=0)
    >>> clf.bidirectional, clf.coupled
    (True, True)
    >>> X = [np.eye(4)[:, :3] * k for k in (0, 1, 1, 0, 1, 0)]   # 4 steps, 3 features
    >>> y = np.array([[0, 1], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]])
    >>> phases = [np.array([0, 0, 1, 1])] * 6                     # one label per step
    >>> clf.fit(X, y, phases=phases).predict(X).shape
    (6, 2)
    >>> [p.shape for p in clf.predict_proba(X)]
    [(6, 2), (6, 2)]
    >>> clf.predict_phases(X[:1])[0].shape
    (4,)
    """
    if name not in PAPER_BASELINES:
        raise ValueError(f"unknown baseline {name!r}; choose one of {list(PAPER_BASELINES)}")
    clash = set(params) & set(PAPER_BASELINES[name])
    if clash:
        raise ValueError(f"{sorted(clash)} are set by the baseline name {name!r}")
    return LSTMSequenceClassifier(**PAPER_BASELINES[name], **params)


def paper_baselines(**params):
    """Build the paper's four recurrent baselines, name -> unfitted classifier.

    Parameters
    ----------
    **params
        :class:`LSTMSequenceClassifier` parameters shared by the four models.

    Returns
    -------
    models : dict of str to LSTMSequenceClassifier
        Keys ``"LSTM"``, ``"Bi-LSTM"``, ``"LSTM Coupled"``, ``"Bi-LSTM Coupled"``.

    Examples
    --------
    >>> from baselines import paper_baselines
    >>> list(paper_baselines(random_state=0))
    ['LSTM', 'Bi-LSTM', 'LSTM Coupled', 'Bi-LSTM Coupled']
    """
    return {name: make_paper_baseline(name, **params) for name in PAPER_BASELINES}
