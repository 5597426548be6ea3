"""Bayesian Specification Inference: LTL task specifications from demonstrations."""

from bsi_sklearn.specification import Specification

__all__ = ["Specification"]
__version__ = "0.1.0"
