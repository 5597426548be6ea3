"""The paper's four recurrent baselines by name, and their training protocol (torch-free)."""

__all__ = ["FAIR_TRAINING", "PAPER_BASELINES"]

#: The four recurrent baselines of the paper's large-force-exercise comparison (its Table
#: "Weighted F1 scores"), as parameters of :class:`baselines.LSTMSequenceClassifier`.
PAPER_BASELINES = {
    "LSTM": {"bidirectional": False, "coupled": False},
    "Bi-LSTM": {"bidirectional": True, "coupled": False},
    "LSTM Coupled": {"bidirectional": False, "coupled": True},
    "Bi-LSTM Coupled": {"bidirectional": True, "coupled": True},
}

#: The training protocol ``bsi-lfe compare`` and ``bsi-lfe study`` give the four baselines
#: (parameters of :class:`baselines.LSTMSequenceClassifier`): early stopping chooses the number
#: of epochs on a 20 % validation split, then a fresh network with the same initial weights
#: is trained on *every* training mission for that many epochs (``refit``), so the networks
#: learn from as many missions as BSI does; mini-batches of 4 sequences give several gradient
#: steps per epoch on a few dozen missions (with the estimator's default of 32, a training
#: set of 14 missions is one step per epoch).
FAIR_TRAINING = {"refit": True, "batch_size": 4}
