"""Labelled event logs drawn from random process trees, each case judged by a hidden rule.

:func:`make_process_log` builds the benchmark data of issue 27 (``benchmarks/bench_event_logs.py``,
``docs/event-log-benchmark.md``): the event logs a process analyst has (pm4py's columns), with
a label per case, at any size.

The process
-----------
Activities are named ``a01``, ``a02``, ... (three digits from 100 activities on). A random
process tree holds each activity once as a leaf; each inner node is a sequence (probability
0.55), an exclusive choice (0.2), a parallel block whose children's runs are interleaved,
every interleaving equally likely (0.15), or a loop (0.1: the body, then with probability 0.35
the redo part and the body again, at most 3 times) over 2 to 4 contiguous groups of its
activities (a loop: body and redo); a leaf is optional (skipped with probability 0.5) with
probability 0.1. A case is one run of the tree (a run with no event is drawn again). Measured
lengths (events a case, 20 trees of 20,000 cases each, ``noise=0``; median, and 10 % to 90 %):
10 activities 7 (2 to 11), 20 activities 8 (2 to 17), 40 activities 23 (4 to 35), 70 activities
35 (11 to 59), 100 activities 37 (5 to 73); the longest case of those 400,000 had 335 events.
Lengths vary much between trees (a choice near the root shortens every case).

Deviations
----------
Each case deviates with probability 0.8: one operation (two with probability 0.5), each a
skip (an event removed; a case keeps one event), a move (an event put back at another
position) or an insert (an activity done once more at a random position), equally likely;
with probability 0.8 the operation concerns one of the rule's activities (the step the rule
controls), else any event or activity. The label is the rule's truth on the deviated case, so
a deviation may keep a case acceptable and a process run may break the rule.

The hidden rule
---------------
A conjunction of clauses over the activities. ``rule="template"``: one to three clauses of
BSI's template on the "occurred" encoding (proposition ``a`` at step t: ``a`` occurred among
the first t events; step 0: nothing yet):

* ``("existence", (a,))``: ``F(a)``, *a occurs*;
* ``("precedence", (a, b))``: ``(!b U a)``, *a occurs, and no b before the first a* (BSI's
  strong until: Declare's ``Existence(a)`` and ``Precedence(a, b)`` together).

``G`` clauses are left out: under the "occurred" encoding every proposition is false at step
0, so ``G(a)`` holds on no case. ``rule="declare"``: one or two clauses outside the template
on that encoding (Declare's LTLf definitions):

* ``("absence", (a,))``: ``G(!a)``, *a never occurs* (in BSI's template only once a negated
  column ``not_a`` is added, e.g. by :class:`~bsi_sklearn.data.preprocessing.NegationAugmenter`,
  as ``G(not_a)``);
* ``("response", (a, b))``: ``G(a -> F(b))``, *every a is eventually followed by a b*;
* ``("at_most_once", (a,))``: ``!F(a & X(F(a)))``, *a occurs at most once* (Declare's
  ``Absence2``).

The "occurred" encoding cannot tell how often or how late an activity occurred, so no formula
on it expresses the last two.

Each clause's pattern is drawn uniformly among the family's, then the clause among that
pattern's candidates: those the process itself keeps on at least 95 % of 300 pilot runs
(absence: at least 50 %, the activity being optional), and not trivially (the ``b`` of a
precedence occurs in at least 20 % of runs, the ``a`` of a response in 20 %, the activity of
an at-most-once in 50 %). A rule is kept when 30 % to 60 % of the pilot's deviated runs violate
it (else, after 60 draws, the rule nearest 45 %). The pilot has its own random streams, so the
rule does not depend on ``n_cases``. Measured on 10 seeds at 10 to 100 activities (2,000 cases,
no noise): 26 % to 64 % of the cases violate the rule, most between 30 % and 60 %. Single
response or at-most-once clauses seldom reach 30 %, so declare rules are most often an absence,
alone or with another clause (40 rules, 10 seeds at 10 to 100 activities: 44 absence, 12
response, 8 at-most-once clauses).

Label noise: each observed label is the clean one flipped with probability ``noise``.
``positive_only=True`` keeps only cases whose observed label is 1 (so with noise, a fraction
of them are unacceptable: their ``clean_labels`` say which), drawing cases until there are
``n_cases``.

Every random number comes from ``numpy.random.Generator`` streams spawned from one
``SeedSequence`` (no Python ``hash``, no global state): a seed gives the same log on every
machine.
"""

from __future__ import annotations

from dataclasses import dataclass
from numbers import Integral, Real

import numpy as np
import pandas as pd
from sklearn.utils import check_random_state

from bsi_sklearn.datasets._process_tree import Uniforms, draw_tree, perturb, simulate, tree_text
from bsi_sklearn.param_validation import Interval, StrOptions, validate_params
from bsi_sklearn.specification import Specification

__all__ = ["ProcessLog", "make_process_log", "activity_names", "rule_holds", "RULE_PATTERNS"]

#: The clause patterns of each rule family.
RULE_PATTERNS = {"template": ("existence", "precedence"),
                 "declare": ("absence", "response", "at_most_once")}
_TEXT = {"existence": "F({0})", "precedence": "(!{1} U {0})", "absence": "G(!{0})",
         "response": "G({0} -> F({1}))", "at_most_once": "!F({0} & X(F({0})))"}
_N_PILOT = 300
_TRIES = 60
_TARGET = (0.3, 0.6)
_CONSTRAINTS = {
    "n_activities": [Interval(Integral, 3, 999, closed="both")],
    "n_cases": [Interval(Integral, 1, None, closed="left")],
    "rule": [StrOptions(("template", "declare"))],
    "noise": [Interval(Real, 0, 1, closed="both")],
    "positive_only": ["boolean"],
    "random_state": ["random_state"],
}


@dataclass(frozen=True, eq=False)
class ProcessLog:
    """A labelled event log of :func:`make_process_log`.

    Attributes
    ----------
    events : DataFrame
        One row per event, pm4py's columns: ``case:concept:name`` (case id), ``concept:name``
        (activity), ``time:timestamp`` (UTC datetimes, increasing within a case); rows by case,
        then time.
    labels : Series of int
        The observed label per case (1 acceptable), after noise; indexed by case id.
    clean_labels : Series of int
        The rule's verdict per case, before noise.
    rule : str
        The hidden rule as LTLf text (``F(a03) & (!a07 U a01)``).
    rule_clauses : tuple of (str, tuple of str)
        The rule's clauses as ``(pattern, activities)`` (see the module docstring).
    family : str
        ``"template"`` or ``"declare"``.
    activities : tuple of str
    tree : str
        The process tree: ``->`` sequence, ``X`` choice, ``+`` parallel, ``*`` loop (body,
        redo), ``?`` optional.
    """

    events: pd.DataFrame
    labels: pd.Series
    clean_labels: pd.Series
    rule: str
    rule_clauses: tuple
    family: str
    activities: tuple
    tree: str

    def cases(self):
        """The activity names of every case, in the order of :attr:`labels`."""
        groups = self.events.groupby("case:concept:name", sort=False)["concept:name"]
        return [list(v) for v in groups.agg(list).reindex(self.labels.index)]

    def specification(self):
        """The hidden rule as a :class:`~bsi_sklearn.Specification`, where the template has it.

        On :class:`~bsi_sklearn.io.EventLogEncoder`'s columns (the occurred encoding, the
        activity names, and the negated columns ``!a`` of its default ``negations=True``):
        existence clauses are eventuals, precedences orders, and absences ``G(!a)``. A rule
        with a response or at-most-once clause has none (the encoding cannot tell how often
        or how late an activity occurred): a ``ValueError`` naming the clause.
        """
        outside = [(p, acts) for p, acts in self.rule_clauses
                   if p not in ("existence", "precedence", "absence")]
        if outside:
            pattern, acts = outside[0]
            raise ValueError(f"the rule's clause {pattern}{tuple(acts)} is outside BSI's "
                             "template on the occurred encoding; only existence, precedence "
                             "and absence clauses have a Specification")
        return Specification(
            globals=["!" + acts[0] for p, acts in self.rule_clauses if p == "absence"],
            eventuals=[acts[0] for p, acts in self.rule_clauses if p == "existence"],
            orders=[acts for p, acts in self.rule_clauses if p == "precedence"])


def activity_names(n_activities):
    """``a01``, ``a02``, ...: zero-padded to two digits, or to the width of ``n_activities``.

    >>> activity_names(3), activity_names(100)[-1]
    (['a01', 'a02', 'a03'], 'a100')
    """
    width = max(2, len(str(int(n_activities))))
    return [f"a{i:0{width}d}" for i in range(1, int(n_activities) + 1)]


def rule_holds(clauses, case):
    """Whether every clause ``(pattern, activities)`` holds on ``case`` (a list of activities)."""
    return all(_holds(pattern, acts, case) for pattern, acts in clauses)


def _holds(pattern, acts, case):
    a = acts[0]
    if pattern == "existence":
        return a in case
    if pattern == "absence":
        return a not in case
    if pattern == "at_most_once":
        return case.count(a) <= 1
    b = acts[1]
    if pattern == "precedence":
        return a in case and b not in case[:case.index(a)]
    if pattern == "response":
        if a not in case:
            return True
        last = len(case) - 1 - case[::-1].index(a)
        return b in case[last + 1:]
    raise ValueError(f"unknown pattern {pattern!r}")


def _candidates(family, runs, n):
    """The family's clauses the process keeps often on ``runs`` (clean runs), not trivially."""
    inf = np.iinfo(np.int64).max
    first = np.full((len(runs), n), inf, dtype=np.int64)
    last = np.full((len(runs), n), -1, dtype=np.int64)
    count = np.zeros((len(runs), n), dtype=np.int64)
    for r, run in enumerate(runs):
        for t, a in enumerate(run):
            first[r, a] = min(first[r, a], t)
            last[r, a] = t
            count[r, a] += 1
    occurs = (count > 0).mean(axis=0)
    rates = {  # per pattern, the fraction of runs keeping each clause, and whether it is relevant
        "existence": ((count > 0).mean(axis=0), np.ones(n, bool)),
        "absence": ((count == 0).mean(axis=0), np.ones(n, bool)),
        "at_most_once": ((count <= 1).mean(axis=0), occurs >= 0.5),
        "precedence": (((first < inf)[:, :, None] & (first[:, :, None] < first[:, None, :]))
                       .mean(axis=0), np.broadcast_to(occurs[None, :] >= 0.2, (n, n))),
        "response": (((last[:, :, None] < 0) | (last[:, None, :] > last[:, :, None]))
                     .mean(axis=0), np.broadcast_to(occurs[:, None] >= 0.2, (n, n))),
    }
    scored = []  # (rate, pattern, activities) of every relevant clause, patterns in order
    for pattern in RULE_PATTERNS[family]:
        keep, relevant = rates[pattern]
        relevant = relevant.copy()
        if relevant.ndim == 2:
            np.fill_diagonal(relevant, False)
        scored += [(float(keep[tuple(ab)]), pattern, tuple(int(i) for i in ab))
                   for ab in np.argwhere(relevant)]
    pool = [(p, ab) for rate, p, ab in scored if rate >= (0.5 if p == "absence" else 0.95)]
    if len(pool) < 3:  # a process that keeps few clauses often (a choice at its root)
        best = sorted(range(len(scored)), key=lambda i: -scored[i][0])[:10]
        pool = [scored[i][1:] for i in sorted(best)]
    return pool


def _draw_rule(family, tree, n, seeds):
    pilot_u = Uniforms(np.random.default_rng(seeds[0]))
    runs = [_run(tree, pilot_u) for _ in range(_N_PILOT)]
    pool = _candidates(family, runs, n)
    rng = np.random.default_rng(seeds[1])
    best, best_gap = None, np.inf
    for _ in range(_TRIES):
        k = int(rng.choice([1, 2, 3], p=[0.3, 0.4, 0.3])) if family == "template" \
            else int(rng.integers(1, 3))
        clauses = _pick_clauses(pool, k, rng)
        u = Uniforms(np.random.default_rng(seeds[2]))  # the same deviations for every draw
        targets = sorted({a for _, acts in clauses for a in acts})
        bad = np.mean([not rule_holds(clauses, perturb(r, targets, n, u)) for r in runs])
        if _TARGET[0] <= bad <= _TARGET[1]:
            return clauses
        if abs(bad - 0.45) < best_gap:
            best, best_gap = clauses, abs(bad - 0.45)
    return best


def _pick_clauses(pool, k, rng):
    """``k`` distinct clauses of ``pool``, pattern first.

    Each draw takes a pattern uniformly among those with clauses left, then one of its clauses
    uniformly, so a pattern with many candidates is not favoured.
    """
    by_pattern = {}
    for i, (pattern, _) in enumerate(pool):
        by_pattern.setdefault(pattern, []).append(i)
    chosen = set()
    while len(chosen) < min(k, len(pool)):
        left = [p for p, idx in by_pattern.items() if any(i not in chosen for i in idx)]
        idx = [i for i in by_pattern[left[rng.integers(len(left))]] if i not in chosen]
        chosen.add(idx[rng.integers(len(idx))])
    return tuple(pool[i] for i in sorted(chosen))


def _run(tree, u):
    while True:
        case = simulate(tree, u)
        if case:
            return case


def _timestamps(lengths, rng):
    """UTC datetimes: cases start 10 minutes apart on average, events 30 minutes apart.

    Whole seconds drawn uniformly (integer draws only: numpy's exponential goes through libm's
    ``log``, whose last bit may differ between machines, and the log's bytes must not).
    """
    starts = np.cumsum(rng.integers(0, 1201, len(lengths)))
    gaps = 1 + rng.integers(0, 3600, int(lengths.sum()))
    within = np.cumsum(gaps)
    ends = np.cumsum(lengths)
    before = np.repeat(np.concatenate([[0], within[ends[:-1] - 1]]), lengths)
    seconds = np.repeat(starts, lengths) + within - before
    base = np.datetime64("2024-01-01T00:00:00", "s")
    return pd.DatetimeIndex(base + seconds.astype("timedelta64[s]")).as_unit("ns").tz_localize(
        "UTC")


def make_process_log(n_activities=20, n_cases=500, *, rule="template", noise=0.05,
                     positive_only=False, random_state=None):
    """A labelled event log: cases of a random process, judged by a hidden rule.

    See the module docstring for the process, the deviations, the rules and the noise.

    Parameters
    ----------
    n_activities : int, default=20
        Activities of the process, 3 to 999.
    n_cases : int, default=500
    rule : {"template", "declare"}, default="template"
        Rules inside BSI's template on the "occurred" encoding, or outside it.
    noise : float, default=0.05
        Probability of flipping each observed label.
    positive_only : bool, default=False
        Keep only cases whose observed label is 1.
    random_state : int, RandomState instance or None, default=None

    Returns
    -------
    log : ProcessLog

    Examples
    --------
    >>> log = make_process_log(10, 200, random_state=0)
    >>> list(log.events.columns)
    ['case:concept:name', 'concept:name', 'time:timestamp']
    >>> log.rule, log.rule_clauses
    ('F(a06)', (('existence', ('a06',)),))
    >>> log.labels.index[:2].tolist(), int(log.labels.sum()), int(log.clean_labels.sum())
    (['case0001', 'case0002'], 87, 85)
    >>> all(rule_holds(log.rule_clauses, c) == bool(y)
    ...     for c, y in zip(log.cases(), log.clean_labels))
    True
    """
    validate_params({"n_activities": n_activities, "n_cases": n_cases, "rule": rule,
                     "noise": noise, "positive_only": positive_only,
                     "random_state": random_state}, _CONSTRAINTS, "make_process_log")
    n, n_cases, noise = int(n_activities), int(n_cases), float(noise)
    seed = check_random_state(random_state).randint(2**31 - 1)
    s_tree, s_p1, s_p2, s_p3, s_cases, s_noise, s_time = np.random.SeedSequence(seed).spawn(7)
    names = activity_names(n)
    tree_rng = np.random.default_rng(s_tree)
    tree = draw_tree([int(i) for i in tree_rng.permutation(n)], Uniforms(tree_rng))
    clauses = _draw_rule(rule, tree, n, (s_p1, s_p2, s_p3))
    targets = sorted({a for _, acts in clauses for a in acts})
    u, noise_rng = Uniforms(np.random.default_rng(s_cases)), np.random.default_rng(s_noise)
    cases, clean, observed = [], [], []
    for _ in range(1000):
        want = n_cases - len(cases)
        if want == 0:
            break
        m = max(64, 2 * want) if positive_only else want
        batch = [perturb(_run(tree, u), targets, n, u) for _ in range(m)]
        ok = np.array([rule_holds(clauses, c) for c in batch], dtype=bool)
        seen = ok ^ (noise_rng.random(m) < noise)
        keep = np.flatnonzero(seen) if positive_only else np.arange(m)
        keep = keep[:want]
        cases += [batch[i] for i in keep]
        clean.append(ok[keep])
        observed.append(seen[keep])
    if len(cases) < n_cases:
        raise RuntimeError("make_process_log: too few acceptable cases were drawn for "
                           "positive_only=True; lower noise or draw another random_state")
    lengths = np.array([len(c) for c in cases], dtype=np.int64)
    width = max(4, len(str(n_cases)))
    ids = np.array([f"case{i:0{width}d}" for i in range(1, n_cases + 1)], dtype=object)
    codes = np.fromiter((a for c in cases for a in c), dtype=np.int64, count=int(lengths.sum()))
    events = pd.DataFrame({
        "case:concept:name": np.repeat(ids, lengths),
        "concept:name": np.array(names, dtype=object)[codes],
        "time:timestamp": _timestamps(lengths, np.random.default_rng(s_time)),
    })
    index = pd.Index(ids, name="case:concept:name")
    rule_clauses = tuple((p, tuple(names[a] for a in acts)) for p, acts in clauses)
    return ProcessLog(
        events=events,
        labels=pd.Series(np.concatenate(observed).astype(np.int64), index=index, name="label"),
        clean_labels=pd.Series(np.concatenate(clean).astype(np.int64), index=index,
                               name="clean_label"),
        rule=" & ".join(_TEXT[p].format(*acts) for p, acts in rule_clauses),
        rule_clauses=rule_clauses, family=rule, activities=tuple(names),
        tree=tree_text(tree, names))
