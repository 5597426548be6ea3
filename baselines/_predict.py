"""The prediction methods of the LSTM baselines: every sequence through the fitted network."""

from __future__ import annotations

import numpy as np
from sklearn.utils.validation import check_is_fitted

from baselines._network import make_batch
from baselines._runtime import torch, torch_threads
from baselines._sequences import check_consistent_sequences, check_sequences

__all__ = ["PredictMixin", "predict_batches"]


def predict_batches(module, data, offsets, lengths, n_outputs, step):
    """Objective probabilities ``(n, n_outputs)`` and per-step phase logits of every sequence.

    The sequences are read shortest first, ``step`` at a time, without gradients; the phase
    logits are ``None`` per sequence when the network has no phase head.
    """
    device = next(module.parameters()).device
    order = np.argsort(lengths, kind="stable")
    proba = np.empty((len(lengths), n_outputs))
    phase_logits = [None] * len(lengths)
    module.eval()
    with torch.no_grad():
        for s in range(0, len(order), step):
            indices = order[s : s + step]
            batch = make_batch(data, offsets, indices, device)
            logits, phases = module(*batch)
            proba[indices] = torch.sigmoid(logits).double().cpu().numpy()
            if phases is not None:
                phases = phases.double().cpu().numpy()
                for k, i in enumerate(indices):
                    phase_logits[i] = phases[k, : lengths[i]]
    return proba, phase_logits


class PredictMixin:
    """The prediction methods of :class:`baselines.LSTMSequenceClassifier`.

    ``predict_proba``, ``predict``, ``predict_phases`` and ``score``, from the fitted
    attributes (``module_``, ``classes_``, ``feature_mean_``, ...).
    """

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

