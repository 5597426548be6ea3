"""``bsi-lfe compare``: BSI against the recurrent baselines on LFE missions (the paper's table).

The paper's large-force-exercise evaluation: four-fold cross-validation over the 24 missions
(18 training / 6 test scenarios per fold), six classifiers (LSTM, Bi-LSTM, LSTM Coupled,
Bi-LSTM Coupled, BSI with Prior 2 and BSI with Prior 3), weighted F1 over both outcomes per
mission objective; and the F1 of the MAP specification fitted on the whole dataset. Beside
the paper's rows, on the same folds: BSI with the CI likelihood, and what a practitioner
would try first (:mod:`baselines.practitioner`: a logistic regression on plain temporal
features, and MiniRocket). Beside the F1, the log loss and Brier score of every row whose model
gives probabilities ("n/a" for the others: :mod:`lfe._probability_scores`).

The comparison's public face; its parts, one job each:

- :mod:`lfe.compare._rows`: the rows (:data:`ROWS`, :data:`BSI_ROWS`...) and the paper's
  values beside them (:data:`PAPER_F1`, :data:`PAPER_MAP_F1`);
- :mod:`lfe.compare._protocol`: the folds, the fit of each row (:func:`fit_bsi`), the scorer
  (:func:`weighted_f1`; both shared with ``bsi-lfe study``) and :func:`compare`;
- :mod:`lfe.compare._result`: :class:`ComparisonResult`, its tables, LaTeX, figure and files.

Its command line (arguments, run, the printed table) is :mod:`lfe.cli._compare`, light at
import.
"""

from lfe.compare._protocol import compare, fit_bsi, weighted_f1
from lfe.compare._result import ComparisonResult, format_value
from lfe.compare._rows import (
    BSI_PRIORS,
    BSI_ROWS,
    CLASSIFIERS,
    MAJORITY,
    PAPER_F1,
    PAPER_MAP_F1,
    ROWS,
    WITHOUT_ROLES,
)

__all__ = [
    "BSI_PRIORS",
    "BSI_ROWS",
    "CLASSIFIERS",
    "ComparisonResult",
    "MAJORITY",
    "PAPER_F1",
    "PAPER_MAP_F1",
    "ROWS",
    "WITHOUT_ROLES",
    "compare",
    "fit_bsi",
    "format_value",
    "weighted_f1",
]
