"""The paper's four recurrent baselines, by name (torch-free, so listing them is cheap)."""

#: The four recurrent baselines of the paper's large-force-exercise comparison (its Table
#: "Weighted F1 scores"), as parameters of :class:`baselines.LSTMSequenceClassifier`.
PAPER_BASELINES = {
    "LSTM": {"bidirectional": False, "coupled": False},
    "Bi-LSTM": {"bidirectional": True, "coupled": False},
    "LSTM Coupled": {"bidirectional": False, "coupled": True},
    "Bi-LSTM Coupled": {"bidirectional": True, "coupled": True},
}
