"""Small synthetic POI problems written independently of the library (shared by tests)."""

import numpy as np
import pandas as pd


def make_poi_problem(n_demos=50, n_threats=5, n_pois=5, chain=(0, 2, 4), n_negative=0,
                     seed=0, always_violated=(4,)):
    """Random demonstrations of 'avoid threats, visit accessible POIs, chain in order'.

    Columns: tau_0..tau_{k-1}, omega_0.., pi_0... Threats listed in ``always_violated`` are
    entered now and then, so G(tau) does not hold for them. Negatives break one rule each.
    """
    rng = np.random.default_rng(seed)
    names = ([f"tau_{i}" for i in range(n_threats)] + [f"omega_{i}" for i in range(n_pois)]
             + [f"pi_{i}" for i in range(n_pois)])
    demos, labels = [], []
    for d in range(n_demos + n_negative):
        negative = d >= n_demos
        pi = rng.random(n_pois) < 0.85
        free = [w for w in range(n_pois) if w not in chain]
        seq = [w for w in chain if pi[w]]
        for w in free:
            if pi[w]:
                seq.insert(int(rng.integers(len(seq) + 1)), w)
        kind = int(rng.integers(3)) if negative else -1
        if kind == 1 and seq:  # skip an accessible POI
            seq.pop(int(rng.integers(len(seq))))
        if kind == 2:  # visit the chain out of order
            in_chain = [w for w in seq if w in chain]
            if len(in_chain) >= 2:
                i, j = seq.index(in_chain[0]), seq.index(in_chain[-1])
                seq[i], seq[j] = seq[j], seq[i]
            else:
                kind = 0
        if kind == 1 and not any(pi):
            kind = 0
        T = 2 * len(seq) + int(rng.integers(2, 6))
        tr = np.zeros((T, len(names)), dtype=np.uint8)
        tr[:, :n_threats] = 1
        for w in range(n_pois):
            tr[:, n_threats + n_pois + w] = pi[w]
        times = np.sort(rng.choice(np.arange(1, T), size=len(seq), replace=False))
        for w, t in zip(seq, times):
            tr[t, n_threats + w] = 1
        for k in always_violated:
            if rng.random() < 0.3:
                tr[int(rng.integers(T)), k] = 0
        if kind == 0:
            tr[int(rng.integers(T)), int(rng.integers(n_threats))] = 0
        demos.append(pd.DataFrame(tr.astype(bool), columns=names))
        labels.append(0 if negative else 1)
    roles = dict(
        global_candidates=[f"tau_{i}" for i in range(n_threats)],
        subtasks=[f"omega_{i}" for i in range(n_pois)],
        conditions={f"omega_{i}": f"pi_{i}" for i in range(n_pois)},
    )
    return demos, np.array(labels), roles


def make_absence_problem(n_demos=24, seed=0):
    """Demonstrations over ``p, q`` whose rule, ``G(!p)``, needs negations to be stated.

    ``p`` never holds in the acceptable demonstrations (every other one) and holds at one step
    or more in the others; ``q`` holds throughout every demonstration. Boolean arrays of 6 steps
    (columns ``p, q``) and 0/1 labels.
    """
    rng = np.random.default_rng(seed)
    X, y = [], []
    for i in range(n_demos):
        t = rng.random((6, 2)) < 0.5
        positive = i % 2 == 0
        t[:, 0] = False if positive else t[:, 0]
        if not positive:
            t[int(rng.integers(6)), 0] = True
        t[:, 1] = True
        X.append(t)
        y.append(int(positive))
    return X, np.array(y)
