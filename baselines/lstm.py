"""LSTM and Bi-LSTM sequence classifiers (standalone and phase-coupled), scikit-learn style."""

from __future__ import annotations

import contextlib
import math
import time
import warnings
from numbers import Integral, Real

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.exceptions import DataConversionWarning
from sklearn.model_selection import train_test_split
from sklearn.utils import check_random_state
from sklearn.utils.class_weight import compute_class_weight
from sklearn.utils.multiclass import type_of_target
from sklearn.utils.validation import check_is_fitted

from baselines._paper import PAPER_BASELINES
from baselines._sequences import (
    check_consistent_sequences,
    check_phases,
    check_sequences,
    length_mask,
    pad_sequences,
    reverse_index,
)
from baselines._torch import require_torch
from bsi_sklearn.param_validation import (
    Interval,
    Satisfies,
    StrOptions,
    validate_params,
)

torch = require_torch()  # with a message naming the [baselines] extra when torch is absent
nn = torch.nn

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

    def __init__(
        self,
        *,
        hidden_size=32,
        num_layers=1,
        bidirectional=False,
        coupled=False,
        n_phases=4,
        pooling="last",
        dropout=0.0,
        max_epochs=200,
        lr=1e-2,
        batch_size=32,
        weight_decay=0.0,
        validation_fraction=0.2,
        patience=20,
        refit=False,
        class_weight=None,
        standardize=True,
        clip_grad_norm=1.0,
        random_state=None,
        verbose=0,
        device="cpu",
        n_threads=1,
    ):
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
        with _torch_threads(self.n_threads):
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
        y01, classes, multi = self._check_targets(y, sequences.n_sequences)
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
        weights = self._label_weights(y01, classes)

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
        train_idx, valid_idx = self._split(y01, split_seed)

        device = torch.device(self.device)
        fork_devices = [device.index or 0] if device.type == "cuda" else []
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
        with torch.random.fork_rng(devices=fork_devices), _deterministic_torch():
            # padded once, for both phases (every batch of either is a slice of these)
            batches = _Batches(data, sequences.offsets, y01, weights, phase_data, device)
            torch.manual_seed(torch_seed)
            module = _RecurrentNet(**self._net_config).to(device)
            self._train(module, batches, train_idx, valid_idx, order_rng, device)
            self.refit_epochs_ = 0
            if self.refit and len(valid_idx) and self.best_epoch_ > 0:
                # Same initial weights, every training sequence, the chosen number of epochs.
                torch.manual_seed(torch_seed)
                module = _RecurrentNet(**self._net_config).to(device)
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

    def _check_targets(self, y, n_sequences):
        """Return ``(y01, classes, multi_output)``; ``y01`` is ``(n, n_outputs)`` float32."""
        if y is None:
            raise ValueError(
                f"{type(self).__name__} requires y to be passed, but the target y is None"
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
            kind = type_of_target(col, input_name="y")
            if kind not in ("binary", "multiclass"):
                raise ValueError(f"Unknown label type: {kind} in {where}; labels must be binary")
            values = np.unique(col)
            if len(values) > 2:
                raise ValueError(
                    "Only binary classification is supported. The type of the target is "
                    f"multiclass: {where} has {len(values)} classes {values.tolist()[:10]}; "
                    f"{type(self).__name__} needs two labels per objective"
                )
            classes.append(values)
            y01[:, k] = np.searchsorted(values, col)
        return y01, classes, multi

    def _split(self, y01, seed):
        """Split the sequences into training and validation indices."""
        n = y01.shape[0]
        all_idx = np.arange(n)
        if not self.validation_fraction or n < 2:
            return all_idx, np.empty(0, dtype=np.int64)
        n_valid = min(max(1, math.ceil(self.validation_fraction * n)), n - 1)
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

    def _label_weights(self, y01, classes):
        """Weight ``(n, n_outputs)`` of every sequence's label in each objective's loss."""
        cw = self.class_weight
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

    def _train(self, module, batches, train_idx, valid_idx, order_rng, device, epochs=None):
        """Train ``module`` with early stopping, or for exactly ``epochs`` epochs (a refit).

        With ``epochs`` the weights after the last epoch are kept in ``module_`` and the
        early-stopping attributes (``history_``, ``best_epoch_``, ...) are left as they are.
        """
        objective_mask = torch.as_tensor(~self._constant, dtype=torch.float32, device=device)
        params = list(module.parameters())
        # foreach: one kernel per step for all parameters instead of one per parameter (the
        # same arithmetic element by element, so the same weights; about 5 % of a fit)
        optimizer = torch.optim.Adam(
            params, lr=self.lr, weight_decay=self.weight_decay, foreach=True
        )

        def batch_loss(indices):
            x, lengths, rev, target, weight, phase_target, mask = batches.batch(indices)
            logits, phase_logits = module(x, lengths, rev)
            bce = nn.functional.binary_cross_entropy_with_logits(
                logits, target, weight=weight, reduction="none",
            )
            loss = (bce.mean(dim=0) * objective_mask).sum()
            if phase_logits is not None:
                loss = loss + nn.functional.cross_entropy(
                    phase_logits[mask], phase_target[mask]
                )
            return loss

        has_valid = len(valid_idx) > 0
        best_loss, best_epoch, best_state = math.inf, 0, None
        history = []
        for epoch in range(1, int(epochs or self.max_epochs) + 1):
            module.train()
            order = order_rng.permutation(train_idx)
            total, count = 0.0, 0
            for s in range(0, len(order), int(self.batch_size)):
                indices = order[s : s + int(self.batch_size)]
                loss = batch_loss(indices)
                optimizer.zero_grad()
                loss.backward()
                if self.clip_grad_norm is not None:
                    nn.utils.clip_grad_norm_(params, self.clip_grad_norm, foreach=True)
                optimizer.step()
                total += float(loss.detach()) * len(indices)
                count += len(indices)
            train_loss = total / count
            if epochs is not None:
                continue
            valid_loss = math.nan
            if has_valid:
                module.eval()
                with torch.no_grad():
                    valid_loss = float(batch_loss(valid_idx))
            monitored = valid_loss if has_valid else train_loss
            history.append({"epoch": epoch, "train_loss": train_loss, "valid_loss": valid_loss})
            if self.verbose > 1:
                print(
                    f"epoch {epoch:4d}  train_loss {train_loss:.4f}  valid_loss {valid_loss:.4f}"
                )
            if not math.isfinite(monitored):
                break
            if monitored < best_loss:
                best_loss, best_epoch = monitored, epoch
                best_state = {k: v.detach().clone() for k, v in module.state_dict().items()}
            elif epoch - best_epoch >= self.patience:
                break
        if epochs is not None:
            module.eval()
            self.module_ = module
            return
        if best_state is not None:
            module.load_state_dict(best_state)
        module.eval()
        self.module_ = module
        self.history_ = history
        self.n_epochs_ = len(history)
        self.best_epoch_ = best_epoch
        self.best_loss_ = best_loss

    # -------------------------------------------------------------- predict

    def _forward_all(self, X):
        """Objective probabilities ``(n, n_outputs)`` and per-step phase logits (or None)."""
        check_is_fitted(self)
        name = type(self).__name__
        sequences = check_sequences(X, estimator_name=name)
        check_consistent_sequences(
            sequences, self.n_features_in_, getattr(self, "feature_names_in_", None), name
        )
        data = ((sequences.data - self.feature_mean_) / self.feature_scale_).astype(np.float32)
        device = next(self.module_.parameters()).device
        lengths = sequences.lengths
        order = np.argsort(lengths, kind="stable")
        proba = np.empty((sequences.n_sequences, self.n_outputs_))
        phase_logits = [None] * sequences.n_sequences
        step = max(int(self.batch_size), 64)
        self.module_.eval()
        with torch.no_grad(), _torch_threads(self.n_threads):
            for s in range(0, len(order), step):
                indices = order[s : s + step]
                batch = _make_batch(data, sequences.offsets, indices, device)
                logits, phases = self.module_(*batch)
                proba[indices] = torch.sigmoid(logits).double().cpu().numpy()
                if phases is not None:
                    phases = phases.double().cpu().numpy()
                    for k, i in enumerate(indices):
                        phase_logits[i] = phases[k, : lengths[i]]
        return proba, phase_logits

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

    # --------------------------------------------------------------- pickle

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
            module = _RecurrentNet(**self._net_config)
            module.load_state_dict(module_state)
            module.eval()
            self.module_ = module


@contextlib.contextmanager
def _deterministic_torch():
    """Run the block with torch's deterministic algorithms on, then restore the setting.

    The CPU kernels these networks use are deterministic already; the flag makes torch raise
    rather than silently pick a nondeterministic kernel (on GPUs, for example). Its companion
    ``torch.utils.deterministic.fill_uninitialized_memory`` (NaN-fill every new tensor, a
    guard against kernels that read memory they did not write) is switched off inside the
    block: it cost about a tenth of a fit (tens of thousands of fills per fit) and changes no
    result of kernels that write their outputs, which every kernel used here does (the fitted
    weights are bit-identical with and without it).
    """
    previous = torch.are_deterministic_algorithms_enabled()
    fill = torch.utils.deterministic.fill_uninitialized_memory
    torch.use_deterministic_algorithms(True)
    torch.utils.deterministic.fill_uninitialized_memory = False
    try:
        yield
    finally:
        torch.use_deterministic_algorithms(previous)
        torch.utils.deterministic.fill_uninitialized_memory = fill


@contextlib.contextmanager
def _torch_threads(n_threads):
    """Use ``n_threads`` torch intra-op threads inside the block, then restore the setting."""
    if n_threads is None:
        yield
        return
    previous = torch.get_num_threads()
    torch.set_num_threads(int(n_threads))
    try:
        yield
    finally:
        torch.set_num_threads(previous)


class _Batches:
    """The training sequences, targets and weights of one ``fit`` as padded tensors, built once.

    Every mini-batch (and the validation batch) is then rows of these tensors cut to the
    batch's longest sequence: the same values that padding the batch on its own gives
    (:func:`_make_batch`), without padding and converting again at every step of every epoch,
    in the early-stopping phase and again in the refit. Memory: ``n_sequences x`` the longest
    length ``x n_features`` floats, the size of one padded batch holding every sequence.
    """

    def __init__(self, data, offsets, y01, weights, phase_data, device):
        n = len(offsets) - 1
        every = np.arange(n)
        padded, lengths = pad_sequences(data, offsets, every)
        self.lengths_np = lengths
        self.x = torch.as_tensor(padded, device=device)
        self.lengths = torch.as_tensor(lengths, device=device)
        self.rev = torch.as_tensor(reverse_index(lengths, padded.shape[1]), device=device)
        self.y = torch.as_tensor(y01, device=device)
        self.weights = torch.as_tensor(weights, device=device)
        self.phases = self.mask = None
        if phase_data is not None:
            phases, _ = pad_sequences(phase_data, offsets, every, fill=0)
            self.phases = torch.as_tensor(phases, device=device)
            self.mask = torch.as_tensor(length_mask(lengths, padded.shape[1]), device=device)

    def batch(self, indices):
        """Inputs, lengths, reversal index, targets, weights, phase targets and step mask."""
        t_max = int(self.lengths_np[indices].max())
        rows = torch.as_tensor(indices, device=self.x.device)
        phases = mask = None
        if self.phases is not None:
            phases = self.phases[rows, :t_max].contiguous()
            mask = self.mask[rows, :t_max].contiguous()
        return (self.x[rows, :t_max].contiguous(), self.lengths[rows],
                self.rev[rows, :t_max].contiguous(), self.y[rows], self.weights[rows],
                phases, mask)


def _make_batch(data, offsets, indices, device):
    """Pad the sequences at ``indices``; return inputs, lengths and reversal index."""
    padded, lengths = pad_sequences(data, offsets, indices)
    return (
        torch.as_tensor(padded, device=device),
        torch.as_tensor(lengths, device=device),
        torch.as_tensor(reverse_index(lengths, padded.shape[1]), device=device),
    )


class _RecurrentNet(nn.Module):
    """Stacked (Bi-)LSTM with an objective head and an optional per-step phase head.

    Each layer is a forward ``nn.LSTM`` and, when bidirectional, a second one run over each
    sequence reversed inside its length (see :func:`baselines._sequences.reverse_index`), so no
    output at a valid step depends on padding.
    """

    def __init__(self, n_features, hidden_size, num_layers, bidirectional, dropout, n_outputs,
                 n_phases, pooling):
        super().__init__()
        self.bidirectional = bidirectional
        self.pooling = pooling
        self.hidden_size = hidden_size
        width = hidden_size * (2 if bidirectional else 1)
        sizes = [n_features] + [width] * (num_layers - 1)
        self.forward_layers = nn.ModuleList(
            nn.LSTM(size, hidden_size, batch_first=True) for size in sizes
        )
        self.backward_layers = nn.ModuleList(
            nn.LSTM(size, hidden_size, batch_first=True) for size in sizes
        ) if bidirectional else None
        self.drop = nn.Dropout(dropout)
        self.objective_head = nn.Linear(width, n_outputs)
        self.phase_head = nn.Linear(width, n_phases) if n_phases else None

    def forward(self, x, lengths, rev_index):
        """Objective logits ``(B, n_outputs)`` and phase logits ``(B, T, n_phases)`` or None."""
        h = x
        for k, layer in enumerate(self.forward_layers):
            if k > 0:
                h = self.drop(h)
            out, _ = layer(h)
            if self.bidirectional:
                idx = rev_index.unsqueeze(-1)
                reversed_in = h.gather(1, idx.expand(-1, -1, h.shape[-1]))
                back, _ = self.backward_layers[k](reversed_in)
                back = back.gather(1, idx.expand(-1, -1, back.shape[-1]))
                out = torch.cat([out, back], dim=-1)
            h = out
        batch = torch.arange(h.shape[0], device=h.device)
        if self.pooling == "last":
            summary = h[batch, lengths - 1]
            if self.bidirectional:
                # the backward direction's final state sits at the first step
                summary = torch.cat([summary[:, : self.hidden_size],
                                     h[:, 0, self.hidden_size :]], dim=-1)
        else:
            mask = (torch.arange(h.shape[1], device=h.device)[None, :] < lengths[:, None])
            mask = mask.unsqueeze(-1)
            if self.pooling == "mean":
                summary = (h * mask).sum(dim=1) / lengths[:, None].to(h.dtype)
            else:
                summary = h.masked_fill(~mask, -math.inf).amax(dim=1)
        logits = self.objective_head(self.drop(summary))
        phase_logits = self.phase_head(h) if self.phase_head is not None else None
        return logits, phase_logits


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
