"""Interpretability reports of a fitted classifier's MAP specification (Markdown and HTML).

:func:`explain` turns a fitted :class:`~bsi_sklearn.BSIClassifier` into a
:class:`SpecificationReport`. The package is split by job: ``wording`` (clause keys and
plain-English sentences), ``document`` (the document model and its Markdown / HTML
renderers), ``figures`` (Matplotlib figures as PNG bytes), ``specification_report`` (the
report object) and ``explain``.
"""

from bsi_sklearn.report.explain import explain
from bsi_sklearn.report.specification_report import SpecificationReport
from bsi_sklearn.report.wording import (
    clause_sentence,
    clause_specification,
    describe_specification,
    ordered_clauses,
    violated_clauses,
)

__all__ = [
    "SpecificationReport",
    "clause_sentence",
    "clause_specification",
    "describe_specification",
    "explain",
    "ordered_clauses",
    "violated_clauses",
]
