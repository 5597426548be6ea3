"""Bayesian Specification Inference: LTL task specifications from demonstrations."""

from bsi_sklearn.classifier import BSIClassifier
from bsi_sklearn.posterior import Posterior
from bsi_sklearn.specification import Specification

__all__ = ["BSIClassifier", "Posterior", "Specification"]
__version__ = "0.1.0"
