"""The paper's experiments on domains with a known ground truth, reproduced.

``run_synthetic`` (POI / threat navigation, Scenarios 1 to 3) and ``run_dinner`` (setting a
dinner table) fit :class:`~bsi_sklearn.BSIClassifier` over a grid of training-set sizes and
random draws, compare the posteriors with the ground truth, and write tables (CSV, Markdown)
and figures (PNG) that put the paper's claims beside the measured values. The command line
is ``bsi reproduce synthetic|dinner``; ``bsi reproduce active``
(:mod:`bsi_sklearn.experiments.active`) compares active-learning query strategies.
"""

from bsi_sklearn.experiments.dinner import run_dinner
from bsi_sklearn.experiments.synthetic import run_synthetic

__all__ = ["run_dinner", "run_synthetic"]
