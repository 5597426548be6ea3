"""The paper's experiments on domains with a known ground truth, reproduced.

``run_synthetic`` (POI / threat navigation, Scenarios 1 to 3) and ``run_dinner`` (setting a
dinner table) fit :class:`~bsi_sklearn.BSIClassifier` over a grid of training-set sizes and
random draws, compare the posteriors with the ground truth, and write tables (CSV, Markdown)
and figures (PNG) that put the paper's claims beside the measured values. The command line
is ``bsi reproduce synthetic|dinner``; ``bsi reproduce active``
(:mod:`bsi_sklearn.experiments.active`) compares active-learning query strategies.

Names are imported on first use (the command line's ``--help`` stays fast).
"""

from bsi_sklearn._lazy import lazy_names

__all__ = ["run_dinner", "run_synthetic"]

_MODULES = {
    "run_dinner": "bsi_sklearn.experiments.dinner",
    "run_synthetic": "bsi_sklearn.experiments.synthetic",
}


__getattr__, __dir__ = lazy_names("bsi_sklearn.experiments", _MODULES, globals())
