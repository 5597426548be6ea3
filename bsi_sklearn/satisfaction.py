"""Which specifications a demonstration satisfies: clause bitsets and the masses they hold.

A specification's clauses are a bitset over the clause slots (:mod:`bsi_sklearn.model.clauses`,
whose :func:`~bsi_sklearn.model.clauses.clause_masks` builds them; the sampler's stopping rule
counts them too); a demonstration satisfies it when every one of those clauses is true on it.
The paper's vote
(:meth:`bsi_sklearn.Posterior.predict_proba`) and the posterior predictive
(:mod:`bsi_sklearn.predictive`) both sum posterior mass over that test, here.
"""

import numpy as np
from numba import njit

from bsi_sklearn.model.clauses import clause_masks

__all__ = ["clause_masks", "satisfies", "satisfied_masses", "vote"]


@njit(cache=True, nogil=True, inline="always")
def satisfies(masks, h, truth_words, i):
    """Whether demonstration ``i`` satisfies specification ``h``: every clause of it holds."""
    for w in range(masks.shape[1]):
        if masks[h, w] & ~truth_words[i, w]:
            return False
    return True


@njit(cache=True, nogil=True)
def satisfied_masses(masks, probs, group, n_groups, truth_words):
    """Posterior masses satisfied and violated, per demonstration and group of specifications.

    A demonstration satisfies a specification when all its clauses hold; the violated mass is
    summed on its own (not 1 minus the first). ``group[h]`` in ``[0, n_groups)``; the vote is
    one group.
    """
    n_d = truth_words.shape[0]
    sat = np.zeros((n_d, n_groups))
    viol = np.zeros((n_d, n_groups))
    for i in range(n_d):
        for h in range(masks.shape[0]):
            if satisfies(masks, h, truth_words, i):
                sat[i, group[h]] += probs[h]
            else:
                viol[i, group[h]] += probs[h]
    return sat, viol


def vote(masks, probs, truth_words):
    """The paper's vote: per demonstration, the mass of the specifications it satisfies."""
    one = np.zeros(masks.shape[0], dtype=np.int64)
    return satisfied_masses(masks, probs, one, 1, truth_words)[0][:, 0].copy()
