"""Independent reference implementations used by several test modules."""

import itertools
from collections import Counter


def program_distribution(prior, n, p_part=0.3, n_new=5.0):
    """Exact distribution of the probabilistic program, by walking every random choice."""
    dist = Counter()
    perms = list(itertools.permutations(range(n)))
    for perm in perms:
        base = 1.0 / len(perms)
        if prior == "linear_chain":
            parent = [-1] * n
            for i in range(1, n):
                parent[perm[i]] = perm[i - 1]
            dist[tuple(parent)] += base
        elif prior == "sets_of_chains":
            for cuts in itertools.product([0, 1], repeat=max(n - 1, 0)):
                parent, last = [-1] * n, -1
                for i, a in enumerate(perm):
                    parent[a] = last
                    last = -1 if (i < n - 1 and cuts[i]) else a
                k = sum(cuts)
                dist[tuple(parent)] += base * p_part**k * (1 - p_part) ** (n - 1 - k)
        else:
            for parent, p in _forest_paths(perm, n, n_new):
                dist[tuple(parent)] += base * p
    return dist


def _forest_paths(perm, n, n_new):
    # State: parent list and per-node size; choices made one element at a time.
    def insert(state, a):
        parent, size = state
        out = []

        def walk(node, prob):
            roots = [v for v in range(n) if parent[v] == node and size[v] > 0]
            total = sum(size[r] for r in roots) + n_new
            new_parent, new_size = list(parent), list(size)
            new_parent[a], new_size[a] = node, 1
            out.append(((new_parent, new_size), prob * n_new / total))
            for r in roots:
                # a goes below r: every ancestor on the path grows by one
                sub = list(size)
                sub[r] += 1
                walk_down(r, prob * size[r] / total, sub)

        def walk_down(node, prob, size_after):
            nonlocal size
            saved = size
            size = size_after
            walk(node, prob)
            size = saved

        walk(-1, 1.0)
        return out

    states = [(([-1] * n, [0] * n), 1.0)]
    for a in perm:
        states = [(s2, p * q) for s, p in states for s2, q in insert(s, a)]
    return [(tuple(s[0]), p) for s, p in states]


def brute_force_posterior(X, y, names, globals_, subtasks, conditions, prior, likelihood,
                          p_global=0.8, p_eventual=0.8, p_part=0.3, n_new=5.0, log_eps=None,
                          flip_prior=None):
    """Posterior over every specification, from first principles (slow, small problems only).

    Uses the program enumeration for the order prior, SampleSubset probabilities for the rest,
    Specification.satisfied_by for satisfaction and the per-demonstration likelihood formulas.
    """
    import math

    from bsi_sklearn import Specification
    from bsi_sklearn.model.likelihood import default_log_epsilon, log_likelihood_reference

    n_g, n = len(globals_), len(subtasks)
    if log_eps is None:
        log_eps = default_log_epsilon(n_g, n)
    orders_dist = program_distribution(prior, n, p_part, n_new)
    logpost = {}
    for parent, p_order in orders_dist.items():
        pairs = []
        for v in range(n):
            a = parent[v]
            while a >= 0:
                pairs.append((subtasks[a], subtasks[v]))
                a = parent[a]
        for tau in itertools.product([0, 1], repeat=n_g):
            for w1 in itertools.product([0, 1], repeat=n):
                spec = Specification(
                    globals=[g for g, b in zip(globals_, tau) if b],
                    eventuals=[w for w, b in zip(subtasks, w1) if b],
                    orders=pairs, conditions=conditions)
                lp = math.log(p_order)
                for bits, p in ((tau, p_global), (w1, p_eventual)):
                    k = sum(bits)
                    lp += k * math.log(p) + (len(bits) - k) * math.log(1 - p)
                sat = [spec.satisfied_by(x, feature_names=names) for x in X]
                lp += log_likelihood_reference(sat, y, spec.n_conjuncts, log_eps, likelihood,
                                               flip_prior)
                logpost[spec] = lp
    mx = max(logpost.values())
    z = math.fsum(math.exp(v - mx) for v in logpost.values())
    return {k: math.exp(v - mx) / z for k, v in logpost.items()}
