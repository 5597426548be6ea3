"""The stochastic agent of the errand tasks: one demonstration, acted out step by step."""

from __future__ import annotations

import numpy as np

__all__ = ["act"]


def _topological_order(subtasks, orders, rng):
    """A random order of ``subtasks`` that respects every precedence in ``orders``."""
    left, plan = list(subtasks), []
    while left:
        ready = [s for s in left if not any(a in left and b == s for a, b in orders)]
        pick = ready[rng.integers(len(ready))]
        plan.append(pick)
        left.remove(pick)
    return plan


def _plan(task, rng, door_closed):
    """The agent's actions for one demonstration, with its mistakes drawn in."""
    r = task.rates
    plan = _topological_order(task.subtasks, task.orders, rng)
    if len(plan) > 1 and rng.random() < r["p_swap"]:
        i = int(rng.integers(len(plan) - 1))
        plan[i], plan[i + 1] = plan[i + 1], plan[i]
    plan = [s for s in plan if rng.random() >= r["p_skip"]]
    if door_closed:
        if task.guarded in plan and rng.random() < r["p_forget"]:
            # opens the door late (after the guarded step) or never
            if rng.random() < 0.5:
                at = plan.index(task.guarded) + 1
                plan.insert(int(rng.integers(at, len(plan) + 1)), task.conditional_step)
        else:
            until = plan.index(task.guarded) if task.guarded in plan else len(plan)
            plan.insert(int(rng.integers(0, until + 1)), task.conditional_step)
    return plan


def act(task, rng):
    """One demonstration of ``task``: a boolean array ``(T, len(task.feature_names))``.

    Parameters
    ----------
    task : ErrandTask
    rng : numpy.random.Generator

    Returns
    -------
    trace : ndarray of shape (T, n_props), dtype bool
    """
    names = task.feature_names
    col = {name: k for k, name in enumerate(names)}
    r = task.rates
    door_closed = bool(rng.random() < 0.5)
    plan = _plan(task, rng, door_closed)
    state = np.zeros(len(names), dtype=bool)
    state[col[task.safety]] = state[col[task.always_on]] = True
    state[col[task.condition]] = door_closed
    for d in task.distractors:
        state[col[d]] = rng.random() < 0.5
    steps = [state.copy()]
    for action in [*plan, None]:  # None: the final wait
        for _ in range(int(rng.integers(0, 3))):
            steps.append(steps[-1].copy())
        if action is None:
            break
        row = steps[-1].copy()
        row[col[action]] = True
        if action == task.conditional_step:
            row[col[task.condition]] = False
        steps.append(row)
    trace = np.array(steps)
    for s in task.momentary:  # a momentary subtask holds on the step it is done only
        k = col[s]
        done = np.flatnonzero(trace[:, k])
        if len(done):
            trace[done[0] + 1:, k] = False
    if rng.random() < r["p_unsafe"] and len(trace) > 1:
        start = int(rng.integers(1, len(trace)))  # safety holds at the first step
        trace[start:start + int(rng.integers(1, 4)), col[task.safety]] = False
    for d in task.distractors:
        k = col[d]
        flips = rng.random(len(trace)) < r["p_flip"]
        flips[0] = False
        trace[:, k] = trace[0, k] ^ (np.cumsum(flips) % 2).astype(bool)
    return trace
