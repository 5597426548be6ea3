"""Errand and pick-and-place tasks drawn at random, for benchmarks on tasks BSI has not seen.

A task of this family is a rule over boolean traces, written here as plain Python (not with
BSI's templates or evaluator), and a stochastic agent that acts it out step by step and makes
mistakes. It was built for issue 20's benchmark (``benchmarks/bench_roles.py``) to measure the
classifier without roles on tasks that come from neither BSI's template sampler nor the paper's
generators. The family was fixed before any result was looked at and is not tuned to results.

The family
----------
Two kinds, each drawn per ``random_state`` by :func:`make_errand_task`:

* ``"errand"``: a robot runs errands in a room. Propositions:

  - ``safe``: the global safety proposition, true at the first step; the agent sometimes
    breaks it for one to three steps after the first.
  - ``powered``: true at every step of every demonstration (a proposition true from the first
    step that no rule mentions).
  - ``door_closed``: the condition, drawn true with probability 0.5 at the first step; it turns
    false when the door is opened.
  - ``opened_door``: the conditional step; true from the step the agent opens the door.
  - subtasks: ``entered`` (the robot enters the room) and one to three errands drawn from
    ``fetched_cup, wiped_table, watered_plant, took_mail, scanned_shelf, charged_tools``; two to
    four subtasks in all, each drawn persistent (true from its step on) or momentary (true on its
    step only). They are partly ordered by a random DAG: every pair of a random permutation
    becomes a precedence with probability 0.4, at least one pair always.
  - distractors: one or two of ``light_on, person_near, phone_ringing``, drawn at random at the
    first step and flipped at every step with a probability drawn per task in [0.1, 0.4].

* ``"pick_place"``: a robot picks an object and places it in a container. Propositions
  ``no_collision`` (safety), ``gripper_ok`` (true throughout), ``container_closed``
  (condition), ``opened_container`` (conditional step), subtasks ``at_object`` (momentary),
  ``grasped`` and ``placed`` (persistent) ordered ``at_object < grasped < placed``, and one
  distractor ``person_near``. The structure is fixed; the agent's error rates are drawn.

The rule (the task's true verdict) is: safety at every step; every subtask at some step; for
every precedence ``a < b`` of the DAG's transitive closure, ``a`` happens and no ``b`` happens
before the first ``a`` (both at one step is fine); and when the condition holds at the first
step, the conditional step happens and the guarded subtask (``entered``, ``placed``) does not
happen before it. :meth:`ErrandTask.labels` computes it from the columns directly.

The agent (:mod:`bsi_sklearn.datasets._errand_agent`) follows a random topological order of the
subtasks, waits zero to two steps before each action, and per demonstration independently, with
rates drawn per task: swaps two adjacent steps of its plan (``p_swap`` in [0.1, 0.3]), skips a
subtask (``p_skip`` per subtask in [0.04, 0.12]), opens a closed door after the guarded step or
never (``p_forget`` in [0.15, 0.35]), breaks safety (``p_unsafe`` in [0.08, 0.2]).

The true roles (what an expert would pass): the safety proposition as the only global
candidate, the subtasks and the conditional step as subtasks, the condition of the conditional
step. :meth:`ErrandTask.specification` is the rule in BSI's template (the conditional step's
``F`` and its precedence over the guarded subtask and the subtask's successors, under the
condition), and :meth:`ErrandTask.ltl` the same rule as LTL text for :mod:`bsi_sklearn.ltl`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from sklearn.utils import Bunch, check_random_state

from bsi_sklearn.datasets._errand_agent import act
from bsi_sklearn.specification import Specification, transitive_closure

__all__ = ["ErrandTask", "make_errand_task", "make_errand_demos", "ERRAND_KINDS"]

ERRAND_KINDS = ("errand", "pick_place")
_ERRANDS = ("fetched_cup", "wiped_table", "watered_plant", "took_mail", "scanned_shelf",
            "charged_tools")
_DISTRACTORS = ("light_on", "person_near", "phone_ringing")


@dataclass(frozen=True)
class ErrandTask:
    """One task of the family: its propositions, its rule and its agent's error rates.

    Attributes
    ----------
    kind : str
        ``"errand"`` or ``"pick_place"``.
    safety, always_on, condition, conditional_step, guarded : str
        The safety proposition, the proposition true throughout, the condition, the step it
        requires, and the subtask that step must precede.
    subtasks : tuple of str
        Unconditional subtasks (the guarded one among them).
    orders : tuple of (str, str)
        The DAG's precedences, *a before b* (not closed).
    momentary : frozenset of str
        Subtasks true on their own step only (the others stay true once done).
    distractors : tuple of str
    rates : dict
        The agent's ``p_swap``, ``p_skip``, ``p_forget``, ``p_unsafe``, ``p_flip``.
    """

    kind: str
    safety: str
    always_on: str
    condition: str
    conditional_step: str
    guarded: str
    subtasks: tuple
    orders: tuple
    momentary: frozenset
    distractors: tuple
    rates: dict

    @property
    def feature_names(self):
        """Column names of the task's traces."""
        return [self.safety, self.always_on, self.condition, self.conditional_step,
                *self.subtasks, *self.distractors]

    @property
    def closure(self):
        """Every precedence the rule requires among the unconditional subtasks."""
        return sorted(transitive_closure(self.orders))

    @property
    def roles(self):
        """The true roles, as ``BSIClassifier`` keyword arguments."""
        return {"global_candidates": [self.safety],
                "subtasks": [self.conditional_step, *self.subtasks],
                "conditions": {self.conditional_step: self.condition}}

    def labels(self, traces):
        """The true verdict of each trace (1 acceptable), from the columns in plain Python.

        Parameters
        ----------
        traces : list of DataFrame
            Columns named as :attr:`feature_names`.

        Returns
        -------
        y : ndarray of shape (n_traces,), dtype int
        """
        return np.array([int(self._ok(t)) for t in traces], dtype=int)

    def _ok(self, trace):
        rows = [dict(zip(trace.columns, map(bool, r))) for r in trace.to_numpy()]

        def first(name):  # first step where ``name`` holds; len(rows) when never
            return next((t for t, row in enumerate(rows) if row[name]), len(rows))

        if not all(row[self.safety] for row in rows):
            return False
        if any(first(s) == len(rows) for s in self.subtasks):
            return False
        for a, b in self.closure:
            if first(a) > first(b):
                return False
        if rows[0][self.condition]:
            step = first(self.conditional_step)
            if step == len(rows) or step > first(self.guarded):
                return False
        return True

    def specification(self):
        """The rule as a :class:`~bsi_sklearn.Specification` of BSI's template."""
        after = [b for a, b in self.closure if a == self.guarded]
        orders = [*self.orders, *((self.conditional_step, b) for b in [self.guarded, *after])]
        return Specification(globals=[self.safety],
                             eventuals=[*self.subtasks, self.conditional_step], orders=orders,
                             conditions={self.conditional_step: self.condition})

    def ltl(self):
        """The rule as infix LTL text (:func:`bsi_sklearn.ltl.parse_ltl` reads it)."""
        parts = [f"G({self.safety})", *(f"F({s})" for s in self.subtasks)]
        parts += [f"(!{b} U {a})" for a, b in self.closure]
        parts.append(f"({self.condition} -> (!{self.guarded} U {self.conditional_step}))")
        return " & ".join(parts)


def _draw_rates(rng):
    return {"p_swap": rng.uniform(0.1, 0.3), "p_skip": rng.uniform(0.04, 0.12),
            "p_forget": rng.uniform(0.15, 0.35), "p_unsafe": rng.uniform(0.08, 0.2),
            "p_flip": rng.uniform(0.1, 0.4)}


def _random_dag(names, rng):
    perm = [names[i] for i in rng.permutation(len(names))]
    pairs = [(perm[i], perm[j]) for i in range(len(perm)) for j in range(i + 1, len(perm))]
    chosen = [p for p in pairs if rng.random() < 0.4]
    if not chosen:
        chosen = [pairs[rng.integers(len(pairs))]]
    return tuple(chosen)


def make_errand_task(kind="errand", random_state=None):
    """Draw one task of the family (see the module docstring).

    Parameters
    ----------
    kind : {"errand", "pick_place"}, default="errand"
    random_state : int, RandomState instance or None, default=None

    Returns
    -------
    task : ErrandTask

    Examples
    --------
    >>> task = make_errand_task("pick_place", random_state=0)
    >>> task.roles["conditions"]
    {'opened_container': 'container_closed'}
    >>> print(task.ltl())  # doctest: +NORMALIZE_WHITESPACE
    G(no_collision) & F(at_object) & F(grasped) & F(placed) & (!grasped U at_object) &
    (!placed U at_object) & (!placed U grasped) &
    (container_closed -> (!placed U opened_container))
    """
    if kind not in ERRAND_KINDS:
        raise ValueError(f"kind must be one of {ERRAND_KINDS}, got {kind!r}")
    rng = np.random.default_rng(check_random_state(random_state).randint(2**31 - 1))
    rates = _draw_rates(rng)
    if kind == "pick_place":
        return ErrandTask(kind, "no_collision", "gripper_ok", "container_closed",
                          "opened_container", "placed", ("at_object", "grasped", "placed"),
                          (("at_object", "grasped"), ("grasped", "placed")),
                          frozenset({"at_object"}), ("person_near",), rates)
    m = int(rng.integers(1, 4))
    errands = [_ERRANDS[i] for i in sorted(rng.choice(len(_ERRANDS), m, replace=False))]
    subtasks = ("entered", *errands)
    momentary = frozenset(s for s in subtasks if rng.random() < 0.5)
    d = int(rng.integers(1, 3))
    distractors = tuple(_DISTRACTORS[i] for i in sorted(rng.choice(3, d, replace=False)))
    return ErrandTask(kind, "safe", "powered", "door_closed", "opened_door", "entered",
                      subtasks, _random_dag(list(subtasks), rng), momentary, distractors, rates)


def make_errand_demos(task, n_demos, random_state=None):
    """Demonstrations of ``task`` by its stochastic agent, labelled by the task's rule.

    Parameters
    ----------
    task : ErrandTask
    n_demos : int
    random_state : int, RandomState instance or None, default=None

    Returns
    -------
    data : sklearn.utils.Bunch
        ``traces`` (list of boolean DataFrames, columns :attr:`ErrandTask.feature_names`),
        ``y`` (true verdicts, 1 acceptable), ``roles`` (the task's true roles),
        ``specification`` (the rule in BSI's template).

    Examples
    --------
    >>> task = make_errand_task("errand", random_state=1)
    >>> data = make_errand_demos(task, 5, random_state=2)
    >>> len(data.traces), data.y.shape, list(data.traces[0].columns) == task.feature_names
    (5, (5,), True)
    """
    rng = np.random.default_rng(check_random_state(random_state).randint(2**31 - 1))
    names = task.feature_names
    traces = [pd.DataFrame(act(task, rng), columns=names) for _ in range(int(n_demos))]
    return Bunch(traces=traces, y=task.labels(traces), roles=task.roles,
                 specification=task.specification())
