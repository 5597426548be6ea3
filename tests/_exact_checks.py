"""Helpers shared by the exact-engine tests: a random problem and two results compared."""

import numpy as np
import pytest

from bsi_sklearn.model import make_model


def _problem(seed, prior, likelihood, n_g, n, n_demos, frac_pos, p_true, epsilon):
    rng = np.random.default_rng(seed)
    truth = (rng.random((n_demos, n_g + n + n * n)) < p_true).astype(np.uint8)
    # Repeated demonstrations and a planted specification that most positives satisfy.
    truth[rng.integers(0, n_demos, n_demos // 3)] = truth[0]
    y = (rng.random(n_demos) < frac_pos).astype(np.int64)
    planted = rng.random(truth.shape[1]) < 0.3
    truth[(y == 1)[:, None] & planted[None, :] & (rng.random(truth.shape) < 0.9)] = 1
    model = make_model(prior=prior, likelihood=likelihood, n_globals=n_g, n_subtasks=n,
                       epsilon=epsilon)
    return truth, y, model


def _as_dict(res):
    return {(tuple(p), tuple(t), tuple(e)): lp for p, t, e, lp in
            zip(res.structures.tolist(), res.tau_masks.tolist(), res.w1_masks.tolist(),
                res.log_prob)}


def _assert_same_posterior(a, b):
    assert a.n_hypotheses == b.n_hypotheses
    assert a.log_evidence == pytest.approx(b.log_evidence, rel=1e-12, abs=1e-9)
    assert np.abs(a.clause_marginals - b.clause_marginals).max(initial=0) < 1e-12
    da, db = _as_dict(a), _as_dict(b)
    # Hypotheses of equal posterior at the cut may be listed either way (rounding), and the
    # dropped mass then differs by theirs.
    cut = min(min(da.values(), default=0), min(db.values(), default=0))
    either = set(da) ^ set(db)
    assert all(abs(da.get(k, db.get(k)) - cut) < 1e-9 for k in either)
    at_cut = sum(np.exp(da.get(k, db.get(k))) for k in either)  # values are log probabilities
    assert abs(a.dropped_mass - b.dropped_mass) <= at_cut + 1e-12
    assert all(abs(da[k] - db[k]) < 1e-11 for k in set(da) & set(db))
