"""What the chains have found: the states they visited and the neighbours of those states.

A Gibbs update weighs every neighbour of the state it moves from exactly, so a state one block
from a visited state is as found as a visited one, once it is in the support. After every round
of ``n_samples="auto"``, :class:`Closure` weighs the neighbours of every visited state
(:func:`~._neighbour_weights.neighbours_within`) and keeps those above the floor with the first
sweep at which a state one block from them was visited; the sampler reports them with the
visited states, and the stopping rule's late mass counts what was *found* late
(:mod:`bsi_sklearn.inference.stopping`). On the diffuse CI posteriors of the stopping tests
(4,655 states) the chains then stop after the first round at TV 0.0008 to exact, where counting
visits alone ran all 10,000 sweeps for the same TV.

Each state's neighbours are weighed once, in the round it is first visited. The work is counted
(``CLOSURE_WORK``): past it the closure is given up for the rest of the fit (the visited states
only grow) and the late mass counts visits, as before.
"""

import math

import numpy as np

from bsi_sklearn.inference._neighbour_weights import neighbours_within

__all__ = ["Closure", "found_states", "CLOSURE_WORK", "CLOSURE_FLOOR"]

#: The most work (:func:`~._neighbour_weights.neighbour_work`, clause-row operations) spent on
#: the neighbours of the visited states over a whole fit: a few seconds.
CLOSURE_WORK = 3e9
#: Neighbours kept: those less than this many nats (log 1e12) below the best state found.
CLOSURE_FLOOR = math.log(1e12)


class Closure:
    """The neighbours of the visited states, weighed once each, within ``CLOSURE_WORK``."""

    def __init__(self, demos, model, max_work=None):
        self.demos, self.model = demos, model
        self.left = float(CLOSURE_WORK if max_work is None else max_work)
        self.given_up = False
        self._near = {}  # a visited state's bytes -> (its neighbours, their log posteriors)

    def update(self, visited, visited_lp, first):
        """The neighbours of ``visited`` above the floor, their log posteriors, when found.

        ``first[i]``: the first recorded sweep at which ``visited[i]`` was visited. Returns
        ``(rows, log_posteriors, first_found)`` (a row once per visited state it neighbours;
        ``first_found`` that state's first visit), or ``None`` once the work has passed the
        budget.
        """
        if self.given_up:
            return None
        floor = float(visited_lp.max()) - CLOSURE_FLOOR
        keys = [row.tobytes() for row in visited]
        new = [i for i, key in enumerate(keys) if key not in self._near]
        if new:
            # The most probable first, so that the budget goes where the mass is.
            new = [new[i] for i in np.argsort(-visited_lp[new], kind="stable")]
            rows, lps, src, done, spent = neighbours_within(visited[new], self.demos,
                                                            self.model, floor, self.left)
            self.left -= spent
            if done < len(new) or self.left < 0:
                self.given_up = True
                self._near.clear()
                return None
            for k, i in enumerate(new):
                mine = src == k
                self._near[keys[i]] = (rows[mine], lps[mine])
        parts = [(self._near[key], first[i]) for i, key in enumerate(keys)]
        rows = np.concatenate([near[0] for near, _ in parts])
        lps = np.concatenate([near[1] for near, _ in parts])
        when = np.concatenate([np.full(len(near[0]), f, dtype=np.int64) for near, f in parts])
        keep = lps >= floor  # the floor rises with the best state found
        return rows[keep], lps[keep], when[keep]


def found_states(visited, visited_lp, first, near):
    """Every state found, its probability among them and the first sweep it was found at.

    ``near`` is :meth:`Closure.update`'s ``(rows, log_posteriors, first_found)``; a state
    both visited and weighed counts from the earlier of the two.
    """
    from bsi_sklearn.inference.mcmc import unique_states

    rows = np.concatenate([visited, near[0]])
    uniq, _, inverse = unique_states(rows, np.zeros(len(rows), dtype=np.int64),
                                     return_inverse=True)
    when = np.full(len(uniq), np.iinfo(np.int64).max)
    np.minimum.at(when, inverse, np.concatenate([first, near[2]]))
    lp = np.empty(len(uniq))
    lp[inverse] = np.concatenate([visited_lp, near[1]])
    probs = np.exp(lp - lp.max())
    return probs / probs.sum(), when
