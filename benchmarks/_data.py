"""Fast synthetic demonstrations for the benchmarks, with exact control of every size.

The domain is the paper's POI / threat task reduced to its propositions: ``n_globals`` threat
propositions ``tau_j`` (true while the agent is clear of threat ``j``), ``n_subtasks`` POI-visit
propositions ``omega_w`` and their accessibility conditions ``pi_w`` (constant over a
demonstration). Every demonstration avoids all threats except the last one (entered now and
then, so ``G(tau_last)`` is not part of the truth), visits every accessible POI, and visits the
POIs of a fixed chain (every other subtask) in order; the other POIs are visited at random
places. Visits are single-step pulses at random times (ties allowed: simultaneous events), so
the distribution of clause truths does not depend on the trace length, which is what the
trace-length sweep needs. Negative demonstrations break one rule each (enter a threat, skip an
accessible POI, or swap two chained POIs).

``bsi_sklearn.datasets.make_poi_threat_demos`` simulates the full 2-D domain (Dubins car,
planner) and is used where the benchmark needs the paper's own demonstrations; it cannot set
the trace length, and it is too slow for 1,000 demonstrations of 10,000 steps.
"""

import numpy as np

__all__ = ["make_demos", "poi_demos"]


def make_demos(n_demos, n_steps, *, n_subtasks=5, n_globals=5, n_negative=0, seed=0,
               jitter=0.2):
    """Random demonstrations of "avoid threats, visit accessible POIs, chain in order".

    Parameters
    ----------
    n_demos : int
        Number of acceptable (positive) demonstrations.
    n_steps : int
        Mean trace length; lengths vary uniformly by ``+-jitter`` around it (at least 1).
    n_subtasks, n_globals : int
        Sizes of the template (columns: ``n_globals`` threats, ``n_subtasks`` POIs and their
        ``n_subtasks`` conditions).
    n_negative : int
        Unacceptable demonstrations, appended after the positives.
    seed : int
    jitter : float
        Relative spread of the trace lengths.

    Returns
    -------
    X : list of ndarray (T_i, n_globals + 2 * n_subtasks), uint8
    y : ndarray of int
    roles : dict
        ``global_candidates``, ``subtasks`` and ``conditions`` by column index, ready for
        ``BSIClassifier(**roles)``.
    """
    rng = np.random.default_rng(seed)
    n_props = n_globals + 2 * n_subtasks
    chain = list(range(0, n_subtasks, 2))
    free = [w for w in range(n_subtasks) if w not in chain]
    X, y = [], []
    for d in range(n_demos + n_negative):
        negative = d >= n_demos
        low = max(1, int(round(n_steps * (1 - jitter))))
        high = max(low, int(round(n_steps * (1 + jitter))))
        T = int(rng.integers(low, high + 1))
        pi = rng.random(n_subtasks) < 0.85
        seq = [w for w in chain if pi[w]]
        for w in free:
            if pi[w]:
                seq.insert(int(rng.integers(len(seq) + 1)), w)
        kind = int(rng.integers(3)) if negative else -1
        if kind == 1 and not seq:
            kind = 0
        if kind == 1:  # skip an accessible POI
            seq.pop(int(rng.integers(len(seq))))
        if kind == 2:  # visit two chained POIs out of order
            in_chain = [i for i, w in enumerate(seq) if w in chain]
            if len(in_chain) >= 2:
                i, j = in_chain[0], in_chain[-1]
                seq[i], seq[j] = seq[j], seq[i]
            else:
                kind = 0
        tr = np.zeros((T, n_props), dtype=np.uint8)
        tr[:, :n_globals] = 1
        tr[:, n_globals + n_subtasks:] = pi
        times = np.sort(rng.integers(0, T, size=len(seq)))
        if kind == 2:  # the swapped pair must really be out of order: no ties
            times = np.sort(rng.choice(T, size=len(seq), replace=False)) if T >= len(seq) \
                else times
        tr[times, n_globals + np.array(seq, dtype=int)] = 1
        if n_globals and rng.random() < 0.3:  # the last threat is entered now and then
            tr[int(rng.integers(T)), n_globals - 1] = 0
        if kind == 0 and n_globals:
            tr[int(rng.integers(T)), int(rng.integers(n_globals))] = 0
        X.append(tr)
        y.append(0 if negative else 1)
    roles = dict(
        global_candidates=list(range(n_globals)),
        subtasks=list(range(n_globals, n_globals + n_subtasks)),
        conditions={n_globals + w: n_globals + n_subtasks + w for w in range(n_subtasks)},
    )
    return X, np.array(y), roles


def poi_demos(n_demos, n_negative=0, seed=0):
    """The paper's synthetic domain (Scenario 2: 5 threats, 5 POIs), when it is importable.

    Returns ``(X, y, roles, source)``; falls back to :func:`make_demos` (5 x 5, about 150
    steps) when ``bsi_sklearn.datasets`` is not available.
    """
    try:
        from bsi_sklearn.datasets import make_poi_threat_demos
    except ImportError:
        X, y, roles = make_demos(n_demos, 150, n_negative=n_negative, seed=seed)
        return X, y, roles, "benchmarks/_data.make_demos (5 threats x 5 POIs)"
    data = make_poi_threat_demos(2, n_demos=n_demos, n_negative=n_negative, n_threats=5,
                                 random_state=seed)
    X = [t.to_numpy(dtype=np.uint8) for t in data.traces]
    names = list(data.feature_names)
    roles = dict(
        global_candidates=[names.index(p) for p in data.roles["global_candidates"]],
        subtasks=[names.index(p) for p in data.roles["subtasks"]],
        conditions={names.index(w): names.index(c) for w, c in data.roles["conditions"].items()},
    )
    return X, data.labels, roles, "bsi_sklearn.datasets.make_poi_threat_demos (scenario 2)"
