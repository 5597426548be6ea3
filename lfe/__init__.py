"""Package lfe (see README)."""
