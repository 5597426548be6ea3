"""Independent reference implementations used by several test modules."""

import itertools
import math
from collections import Counter

import numpy as np


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
                j = max(n - 1 - k, 0)  # the places not cut
                if p_part == "learned":  # the integral of p^k (1 - p)^j over (0, 1)
                    w = math.factorial(k) * math.factorial(j) / math.factorial(k + j + 1)
                else:
                    w = p_part**k * (1 - p_part) ** j
                dist[tuple(parent)] += base * w
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


def ltlf_holds(tree, trace, t=0):
    """An LTLf tree (``parse_ltlf``'s, atoms already columns of ``trace``) at step ``t``.

    By the definitions, quantifying over the later steps: no recurrence shared with the
    package's kernels. ``X`` is the strong next, ``WX`` the weak one.
    """
    from bsi_sklearn.specification.templates import OPCODES as O

    op, last = tree[0], len(trace) - 1
    kids = tree[1:]
    if op == O["atom"]:
        return bool(trace[t][kids[0]])
    if op in (O["true"], O["false"]):
        return op == O["true"]
    if op == O["not"]:
        return not ltlf_holds(kids[0], trace, t)
    if op in (O["and"], O["or"], O["implies"], O["equiv"]):
        a, b = (ltlf_holds(k, trace, t) for k in kids)
        return {O["and"]: a and b, O["or"]: a or b, O["implies"]: (not a) or b,
                O["equiv"]: a == b}[op]
    if op == O["next"]:
        return t < last and ltlf_holds(kids[0], trace, t + 1)
    if op == O["weak_next"]:
        return t == last or ltlf_holds(kids[0], trace, t + 1)
    if op == O["eventually"]:
        return any(ltlf_holds(kids[0], trace, u) for u in range(t, last + 1))
    if op == O["globally"]:
        return all(ltlf_holds(kids[0], trace, u) for u in range(t, last + 1))
    a, b = kids
    if op == O["until"]:
        return any(ltlf_holds(b, trace, u) and all(ltlf_holds(a, trace, v) for v in range(t, u))
                   for u in range(t, last + 1))
    # a R b = !(!a U !b)
    return not any(not ltlf_holds(b, trace, u)
                   and all(not ltlf_holds(a, trace, v) for v in range(t, u))
                   for u in range(t, last + 1))


def instance_holds(template, columns, trace):
    """Whether one pattern instance (template, column of each slot) holds on ``trace``."""
    from bsi_sklearn.specification.templates import get_template, parse_ltlf

    t = get_template(template)
    table = dict(zip(t.slots, columns))

    def bind(node):
        if node[0] == 0 and isinstance(node[1], str):  # an atom: its slot's column
            return (0, table[node[1]])
        return (node[0], *(bind(k) for k in node[1:]))

    return ltlf_holds(bind(parse_ltlf(t.formula)), np.asarray(trace))


def brute_force_posterior(X, y, names, globals_, subtasks, conditions, prior, likelihood,
                          p_global=0.8, p_eventual=0.8, p_part=0.3, n_new=5.0, log_eps=None,
                          flip_prior=None, patterns=()):
    """Posterior over every specification, from first principles (slow, small problems only).

    Uses the program enumeration for the order prior, SampleSubset probabilities for the rest,
    Specification.satisfied_by for satisfaction and the per-demonstration likelihood formulas.
    ``patterns``: ``(template, proposition names, inclusion probability)`` of each pattern
    candidate, its truth by :func:`instance_holds` (the definitions), each an independent
    inclusion; ``log_eps`` then counts them among the global slots.
    """
    import math

    from bsi_sklearn import Specification
    from bsi_sklearn.model.likelihood import default_log_epsilon, log_likelihood_reference

    n_g, n = len(globals_), len(subtasks)
    if log_eps is None:
        log_eps = default_log_epsilon(n_g + len(patterns), n)
    col = {name: j for j, name in enumerate(names)}
    pat_truth = [[instance_holds(t, [col[q] for q in props], x) for x in X]
                 for t, props, _ in patterns]
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
                paper = Specification(
                    globals=[g for g, b in zip(globals_, tau) if b],
                    eventuals=[w for w, b in zip(subtasks, w1) if b],
                    orders=pairs, conditions=conditions)
                sat_paper = [paper.satisfied_by(x, feature_names=names) for x in X]
                lp0 = math.log(p_order)
                for bits, p in ((tau, p_global), (w1, p_eventual)):
                    k = sum(bits)
                    if p == "learned":  # the integral of p^k (1 - p)^(m - k) over (0, 1)
                        m = len(bits)
                        lp0 += math.log(math.factorial(k) * math.factorial(m - k)
                                        / math.factorial(m + 1))
                    else:
                        lp0 += k * math.log(p) + (len(bits) - k) * math.log(1 - p)
                for pbits in itertools.product([0, 1], repeat=len(patterns)):
                    chosen = [k for k, b in enumerate(pbits) if b]
                    spec = Specification(paper.globals, paper.eventuals, paper.orders,
                                         conditions, [patterns[k][:2] for k in chosen])
                    lp = lp0 + sum(math.log(q) if b else math.log1p(-q)
                                   for b, (_, _, q) in zip(pbits, patterns))
                    sat = [s and all(pat_truth[k][i] for k in chosen)
                           for i, s in enumerate(sat_paper)]
                    lp += log_likelihood_reference(sat, y, spec.n_conjuncts, log_eps,
                                                   likelihood, flip_prior)
                    logpost[spec] = lp
    mx = max(logpost.values())
    z = math.fsum(math.exp(v - mx) for v in logpost.values())
    return {k: math.exp(v - mx) / z for k, v in logpost.items()}


def all_traces(n_props, max_len=4):
    """Every trace of 1 to ``max_len`` steps over ``n_props`` propositions (tuples of rows)."""
    steps = list(itertools.product([0, 1], repeat=n_props))
    for length in range(1, max_len + 1):
        yield from itertools.product(steps, repeat=length)


def stack_traces(traces):
    """``(data, offsets)`` of traces stacked as ``Traces`` holds them (uint8, int64)."""
    data = np.array([row for tr in traces for row in tr], dtype=np.uint8)
    offsets = np.concatenate([[0], np.cumsum([len(tr) for tr in traces])]).astype(np.int64)
    return data, offsets
