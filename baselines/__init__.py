"""Package baselines (see README)."""
