"""Bayesian Specification Inference: LTL task specifications from demonstrations.

The public names are imported on first use, so that ``import bsi_sklearn`` and the command
lines' ``--help`` start in a fraction of a second (scikit-learn and numba load with the
classifier).
"""

from bsi_sklearn._lazy import lazy_names
from bsi_sklearn._numba_cache import configure_numba_cache

configure_numba_cache()  # before any compiled function: a read-only installation imports too

__all__ = ["BSIClassifier", "Posterior", "Specification"]
__version__ = "0.1.0"

_MODULES = {"BSIClassifier": "bsi_sklearn.classifier", "Posterior": "bsi_sklearn.posterior",
            "Specification": "bsi_sklearn.specification"}


__getattr__, __dir__ = lazy_names("bsi_sklearn", _MODULES, globals())
