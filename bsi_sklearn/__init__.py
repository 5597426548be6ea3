"""Bayesian Specification Inference: LTL task specifications from demonstrations."""

from bsi_sklearn._numba_cache import configure_numba_cache

configure_numba_cache()  # before any compiled function: a read-only installation imports too

from bsi_sklearn.classifier import BSIClassifier  # noqa: E402
from bsi_sklearn.posterior import Posterior  # noqa: E402
from bsi_sklearn.specification import Specification  # noqa: E402

__all__ = ["BSIClassifier", "Posterior", "Specification"]
__version__ = "0.1.0"
