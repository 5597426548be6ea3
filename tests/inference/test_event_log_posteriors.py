"""On event logs small enough to enumerate, the sampler's posterior is the exact one.

Generated labelled logs (``make_process_log``: a random process, a hidden rule of the template,
flipped labels) encoded as "activity occurred so far", every activity a subtask under the
inferred roles: the posterior users bring from process logs, peaked by hundreds of cases.
"""

import numpy as np
import pytest

from bsi_sklearn import BSIClassifier
from bsi_sklearn.datasets import make_process_log
from bsi_sklearn.inference.diagnostics import total_variation
from bsi_sklearn.io import EventLogEncoder, read_event_log


def _encoded_log(n_activities, n_cases, seed, **kw):
    log = make_process_log(n_activities, n_cases, random_state=seed, **kw)
    cases, y, _ = read_event_log(log.events, labels=log.labels)
    return EventLogEncoder().fit_transform(cases), y, log


@pytest.mark.slow
@pytest.mark.parametrize("seed, n_activities, n_cases, spread", [
    (0, 6, 200, False), (1, 7, 300, False), (2, 8, 400, False),  # peaked: one specification
    (4, 8, 60, True), (8, 10, 40, True)])                        # spread over several
@pytest.mark.parametrize("likelihood", ["cb", "calibrated"])
def test_the_sampler_agrees_with_exact_enumeration_on_event_logs(seed, n_activities, n_cases,
                                                                 spread, likelihood):
    X, y, _ = _encoded_log(n_activities, n_cases, seed)
    exact = BSIClassifier(inference="exact", likelihood=likelihood, random_state=0).fit(X, y)
    probs = exact.posterior_.probabilities
    if likelihood == "cb":  # CB's size principle: one specification unless the data are few
        assert (probs[0] < 0.9) == spread
    sampled = BSIClassifier(inference="mcmc", likelihood=likelihood, n_samples=2000,
                            random_state=0).fit(X, y)
    assert exact.roles_ == sampled.roles_ and len(exact.roles_["subtasks"]) >= n_activities - 2
    assert total_variation(exact.posterior_, sampled.posterior_) < 0.05
    if len(probs) == 1 or probs[0] > 1.5 * probs[1]:  # a MAP that ties with no other
        assert sampled.map_specification_ == exact.map_specification_


def test_the_default_fit_recovers_a_template_rule_from_200_cases():
    X, y, log = _encoded_log(8, 300, seed=3, noise=0.0)
    clf = BSIClassifier(random_state=0).fit(X[:200], y[:200])
    assert clf.inference_ == "exact"
    rule = log.specification()
    map_spec = clf.map_specification_
    # The hidden rule's clauses are all in the MAP (others may be untested by the data).
    assert rule.eventuals <= map_spec.eventuals and rule.orders <= map_spec.orders
    assert np.mean(clf.predict(X[200:]) == y[200:]) >= 0.95
