"""Issue 19's target: no default fit returns a MAP that no acceptable demonstration satisfies.

Published samples2LTL / Scarlet files (read from ``../shared``, skipped when absent), fitted
as a user would: every proposition and its negation (``NegationAugmenter``), every default of
``BSIClassifier``. Before issue 19 the sampler returned contradictions such as
``G(p) & G(!p)`` on such files, rejecting every trace.
"""

import numpy as np
import pytest
from _shared_data import BENCHMARKS_DATA

from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.preprocessing import NegationAugmenter
from bsi_sklearn.io import load_trace_file

DATA = BENCHMARKS_DATA
FILES = sorted(DATA.rglob("*.trace"))[::40] if DATA.is_dir() else []


@pytest.mark.shared_data
@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(DATA)))
def test_the_default_map_satisfies_some_acceptable_demonstration(path):
    X, y, _ = load_trace_file(path)
    y = np.asarray(y)
    if X[0].shape[1] > 7:
        pytest.skip("more than 7 propositions (14 candidates with negations): slow here")
    Xa = NegationAugmenter().fit_transform(X)
    clf = BSIClassifier(random_state=0).fit(Xa, y)
    names = list(Xa[0].columns)
    positives = [x for x, label in zip(Xa, y) if label == 1]
    assert any(clf.map_specification_.satisfied_by(x.to_numpy(), feature_names=names)
               for x in positives), clf.map_specification_.to_ltl()
