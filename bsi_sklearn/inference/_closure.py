"""What the chains have found: the states they visited, and what those states lead to.

A Gibbs update weighs every neighbour of the state it moves from exactly, so a state one block
from a visited state is as found as a visited one, once it is in the support. After every round
of ``n_samples="auto"``, :class:`Closure` weighs the neighbours of every visited state
(:func:`~._neighbour_weights.neighbours_within`), keeps those above the floor, and weighs in
turn the neighbours of every state it finds within ``CLOSURE_EXPAND`` of the best; from the
ties of the best it also weighs the states that exchange two subtasks' places
(:mod:`~._exchanges`): a plateau of equally probable states (the interchangeable orders of an
event log's subtasks, often two blocks apart across a valley and one exchange apart) is found
whole once one of its states is visited. Each found state carries the first sweep at which a
visited state it was reached from was visited; the sampler reports the found states with the
visited ones, and the stopping rule's late mass counts what was *found* late
(:mod:`bsi_sklearn.inference.stopping`).

Measured: the diffuse CI posteriors of the stopping tests (3,383-4,672 states) stop after the
first round at TV 0.0002 or less to exact, where counting visits ran 4,000-10,000 sweeps for TV
0.0002-0.0009; the plateau of 344 specifications of ``make_process_log(40, 1000,
random_state=2)`` is found whole after 500 sweeps (the chains had visited 343), where visits
ran 2,000. With the exchanges from the ties, the plateau of 11,248 specifications of
``make_process_log(40, 286, random_state=0)`` (200 training cases) is found whole after the
first round (19 s of weighing, 1.7 ms a state), and the fit stops there: 35 s, where the chains
ran all 10,000 sweeps (261 s) and listed 10,887 of them.

Each state's neighbours are weighed once. The work is counted (``CLOSURE_WORK``, clause-row
operations, about 1e10 a second on a 2-core Xeon), and so is the memory of what is kept
(``CLOSURE_BYTES``); the ties' work and memory go first to their own budgets
(``PLATEAU_SHARE`` of the sampling they can save, ``PLATEAU_BYTES``), so that a posterior
without ties costs what it did. Past them the closure is given up for the rest of the fit (the
visited states only grow) and the late mass counts visits, as before.
"""

import heapq
import itertools
import math

import numpy as np
from numba import njit

from bsi_sklearn._unique_rows import row_keys
from bsi_sklearn.inference._exchanges import ExchangeWeigher
from bsi_sklearn.inference._neighbour_weights import NeighbourWeigher

__all__ = ["Closure", "found_states", "found_by_chain", "CLOSURE_WORK", "CLOSURE_BYTES",
           "PER_SAMPLING", "CLOSURE_FLOOR", "CLOSURE_EXPAND"]

#: The most work (:func:`~._neighbour_weights.neighbour_work`, clause-row operations) spent on
#: weighing neighbours over a whole fit: a few seconds (the 344-state plateau above: 5.5e9,
#: 0.6 s).
CLOSURE_WORK = 3e10
#: The most memory the weighed neighbours may hold, in bytes, each kept row counted as its
#: int16 row, its bytes key and their references (``4 n_cols + 64``). The work above does not
#: bound it on small problems, where a state is cheap to weigh: the 7-proposition file 0046 of
#: the mixing benchmark (11 demonstrations) keeps 609,089 rows, about 90 MB by this count.
CLOSURE_BYTES = 2**27
#: Neighbours kept: those less than this many nats (log 1e12) below the best state found.
CLOSURE_FLOOR = math.log(1e12)
#: Found states whose own neighbours are weighed too: those less than this many nats (log
#: 1e4) below the best state found. On the mixing benchmark's slowest problems log 1e3
#: stopped at TV 0.0016-0.0044, log 1e6 at 0.0000 but up to 4x slower; log 1e4: 0.0006-0.0011.
CLOSURE_EXPAND = math.log(1e4)
#: Found states whose exchanges of two subtasks' places are weighed too (:mod:`._exchanges`):
#: those this many nats or less below the best state found, the ties of a plateau of equally
#: probable specifications (interchangeable subtasks of an event log's orders), which are two
#: blocks apart across a valley and one exchange apart.
EXCHANGE_LEVEL = 1e-9
#: The ties' work (their neighbours and exchanges weighed) may go beyond ``CLOSURE_WORK`` up
#: to this share of the sampling the chains may still do (:func:`~.mcmc.sampling_count`, in
#: the closure's units: it counts about 1e10 a second on a 2-core Xeon, the chains 7e8): a
#: plateau found whole stops the chains rounds earlier. Other states stay within
#: ``CLOSURE_WORK``, so posteriors without ties cost what they did. ``PER_SAMPLING``: the
#: closure's units per unit of the chains' work, the same time.
PER_SAMPLING = 1e10 / 7e8
PLATEAU_SHARE = 0.25 * PER_SAMPLING
#: The memory the ties' lists may hold beyond ``CLOSURE_BYTES``, in bytes: every distinct key
#: once (its int16 row's bytes and ``KEY_BYTES`` of object and dictionary entry), and
#: ``REF_BYTES`` per entry of a list (two list slots and a float).
PLATEAU_BYTES = 2**27
KEY_BYTES = 96
REF_BYTES = 40

_NEVER = int(np.iinfo(np.int64).max)  # a time later than every sweep


def _draw(own, general, amount):
    # `amount` taken from `own` while it lasts, the rest from `general`: both left after.
    own -= amount
    return (own, general) if own >= 0 else (0.0, general + own)


class Closure:
    """What the chains found, weighed once each, within ``CLOSURE_WORK``.

    The visited states, their neighbours, and so on through the most probable states.
    """

    def __init__(self, demos, model, max_work=None, sampling_work=0.0):
        self.demos, self.model = demos, model
        self.left = float(CLOSURE_WORK if max_work is None else max_work)
        # the ties' own budget, beyond which they are charged to the one above
        self.tied_left = PLATEAU_SHARE * float(sampling_work)
        self.tied_bytes_left = float(PLATEAU_BYTES)
        self._held = {}  # every neighbour's key, once: the lists share them
        self._tie_cost = (np.inf, np.inf)  # the least work and memory a tie has taken
        self.bytes_left = float(CLOSURE_BYTES)
        self.given_up = False
        # a weighed state's bytes -> its neighbours, their log posteriors and their bytes
        self._near = {}
        self._levels = (np.inf, np.inf)  # the floor and the expansion level of the last update
        self._weigher = None  # its scratch space, allocated at the first state weighed
        self._exchanger = None
        self._exchanged = set()  # the weighed states whose lists hold their exchanges too
        # The states the last completed update traversed and its floor (see `complete`).
        self._traversed, self._traversed_floor = frozenset(), np.inf

    def _charge(self, spent, tied):
        # A tie's work is charged to the ties' budget while it lasts.
        if tied:
            self.tied_left, self.left = _draw(self.tied_left, self.left, spent)
        else:
            self.left -= spent

    def _weigh(self, row, floor, tied=False):
        # Weigh the neighbours of a state not weighed yet; False past the budget.
        if self._weigher is None:
            self._weigher = NeighbourWeigher(self.demos, self.model)
        near, lps, spent = self._weigher.one(row.astype(np.int64), floor)
        self._charge(spent, tied)
        keys = self._keys_of(near, tied)
        if self.left < 0 or self.bytes_left < 0:
            self._give_up()
            return False
        # Python floats and bytes: the traversals below run over them element by element
        self._near[row.tobytes()] = (lps.tolist(), keys)
        return True

    def _keys_of(self, near, tied):
        # The neighbours' keys, each distinct key held once, and their memory charged: a
        # tie's list to the ties' memory while it lasts (what is held: the distinct keys once,
        # and each entry's slots and float), other lists as before (a row, its key and their
        # references per entry).
        held = self._held
        before = len(held)
        keys = [held.setdefault(k, k) for k in row_keys(near)]
        if not tied:
            self.bytes_left -= len(near) * (4 * near.shape[1] + 64)
            return keys
        self.tied_bytes_left, self.bytes_left = _draw(
            self.tied_bytes_left, self.bytes_left,
            (len(held) - before) * (2 * near.shape[1] + KEY_BYTES) + len(near) * REF_BYTES)
        return keys

    def _weigh_tie(self, key, floor, n_pending):
        # Weigh a tie's neighbours (unless weighed already) and exchanges. False past the
        # budgets, or as soon as the ties found and not weighed yet would pass them at the
        # least work and memory a tie has cost so far (a plateau too large to list is given up
        # at once, not after the budgets are spent).
        work, held = self.left + self.tied_left, self.bytes_left + self.tied_bytes_left
        if key not in self._near and not self._weigh(np.frombuffer(key, dtype=np.int16),
                                                     floor, True):
            return False
        if not self._exchange(key, floor):
            return False
        work -= self.left + self.tied_left
        held -= self.bytes_left + self.tied_bytes_left
        self._tie_cost = (min(self._tie_cost[0], work), min(self._tie_cost[1], held))
        if (n_pending * self._tie_cost[0] > self.left + self.tied_left
                or n_pending * self._tie_cost[1] > self.bytes_left + self.tied_bytes_left):
            self._give_up()
            return False
        return True

    def _give_up(self):
        self.given_up = True
        self._near.clear()
        self._held.clear()
        self._traversed, self._traversed_floor = frozenset(), np.inf

    def complete(self, floor):
        """The keys of states whose every neighbour at or above ``floor`` the last update found.

        The states that update traversed: it kept each of their neighbours at or above its
        own floor among the states it returned, so where ``floor`` is no lower, a caller
        holding those states need not weigh their neighbours again. Empty where the floor is
        lower, or once the closure is given up.
        """
        return self._traversed if floor >= self._traversed_floor else frozenset()

    def _exchange(self, key, floor):
        # Add to a weighed state's list the states that exchange two of its subtasks' places
        # (:mod:`._exchanges`); False past the budget.
        if self._exchanger is None:
            self._exchanger = ExchangeWeigher(self.demos, self.model)
        near, lps, spent = self._exchanger.within(np.frombuffer(key, dtype=np.int16), floor)
        self._charge(spent, True)
        keys = self._keys_of(near, True)
        if self.left < 0 or self.bytes_left < 0:
            self._give_up()
            return False
        own_lps, own_keys = self._near[key]
        own_lps.extend(lps.tolist())
        own_keys.extend(keys)
        self._exchanged.add(key)
        return True

    def update(self, visited, visited_lp, first):
        """The states found one block from a weighed state, their log posteriors, and when.

        The weighed states are the visited ones and, from them, every state found within
        ``CLOSURE_EXPAND`` of the best (of the visited states and of those found by earlier
        calls; ``CLOSURE_FLOOR`` below it, a state is not kept): a plateau of equally
        probable states is found whole as soon as one of its states is visited. A state is
        found at the first visit of a visited state it is reached from (through weighed
        states); ``first[i]`` is the first recorded sweep at which ``visited[i]`` was visited.
        Returns ``(rows, log_posteriors, first_found)`` of the states found this way (visited
        ones among them where they are found so), or ``None`` once the work has passed the
        budget.
        """
        if self.given_up:
            return None
        best = float(visited_lp.max())
        for lps, _ in self._near.values():
            if lps:
                best = max(best, max(lps))
        floor, expand = best - CLOSURE_FLOOR, best - CLOSURE_EXPAND
        self._levels = floor, expand
        # Visited states first, then the states found within `expand`, earliest first: a
        # state's time is the least time of a weighed state it is one block from.
        when, lp_of, heap = {}, {}, []
        visited_at = {}  # the log posteriors of the visited states
        for key, t, lp in zip(row_keys(visited), first.tolist(), visited_lp.tolist()):
            visited_at[key] = lp
            if t < when.get(key, _NEVER):
                when[key] = t
                heapq.heappush(heap, (t, key))
        tied = best - EXCHANGE_LEVEL
        exchanges = self.model.n >= 2
        weighed = set(when)  # the visited states, then those found within `expand`
        done = set()
        pending = set()  # ties found whose exchanges are not weighed yet
        while heap:
            t, key = heapq.heappop(heap)
            if key in done or t > when[key]:
                continue
            done.add(key)
            is_tied = exchanges and lp_of.get(key, visited_at.get(key, -np.inf)) >= tied
            if is_tied and key not in self._exchanged:
                pending.discard(key)
                if not self._weigh_tie(key, floor, len(pending)):
                    return None
            elif key not in self._near and not self._weigh(
                    np.frombuffer(key, dtype=np.int16), floor):
                return None
            lps, keys = self._near[key]
            for lp, k in zip(lps, keys):
                if lp < floor:  # the floor rises with the best state found
                    continue
                if t < when.get(k, _NEVER):
                    when[k] = t
                    lp_of[k] = lp
                    if lp >= expand:
                        weighed.add(k)
                    if k in weighed:
                        heapq.heappush(heap, (t, k))
                        if lp >= tied and exchanges and k not in self._exchanged:
                            pending.add(k)
                elif k not in lp_of:
                    lp_of[k] = lp
        self._traversed, self._traversed_floor = frozenset(done), floor
        found = list(lp_of)
        width = visited.shape[1]
        return (np.frombuffer(b"".join(found), dtype=np.int16).reshape(len(found), width),
                np.array([lp_of[k] for k in found], dtype=float),
                np.array([when[k] for k in found], dtype=np.int64))


def found_states(visited, visited_lp, first, near):
    """Every state found, its probability among them, the first sweep it was found at, its key.

    ``near`` is :meth:`Closure.update`'s ``(rows, log_posteriors, first_found)``; a state
    both visited and weighed counts from the earlier of the two. The keys are the rows' bytes
    (as int16), in the order of the other two arrays.
    """
    at, lps, when = {}, [], []
    for rows, row_lp, row_first in ((visited, visited_lp, first), near):
        for key, lp, t in zip(row_keys(rows), row_lp.tolist(), row_first.tolist()):
            i = at.setdefault(key, len(lps))
            if i == len(lps):
                lps.append(lp)
                when.append(t)
            elif t < when[i]:
                when[i] = t
    lps = np.array(lps)
    probs = np.exp(lps - lps.max())
    return probs / probs.sum(), np.array(when, dtype=np.int64), list(at)


def found_by_chain(closure, visited, per_chain, keys):
    """For each chain, what its visited states lead to, as the last update found.

    ``per_chain`` holds each chain's visited states (indices into ``visited``); ``keys`` is
    :func:`found_states`' order. Returns index arrays into it, one per chain, sorted.

    The same traversal as :meth:`Closure.update` from one chain's visited states: the states
    themselves, and the states above the floor one block (or one exchange, from a tie) from
    them or from a state so found within ``CLOSURE_EXPAND`` of the best. Call after the
    update (it weighed every state this traverses). The found states are numbered by
    ``keys`` and the weighed states' neighbour lists become one array of edges (every state a
    chain can reach is among those found, as the update traversed from every visited
    state), walked in compiled code once per chain.
    """
    index = {k: i for i, k in enumerate(keys)}
    starts, targets, lps = [0] * (len(keys) + 1), [], []
    for k, i in index.items():
        near = closure._near.get(k)
        if near is not None:
            near_lps, near_keys = near
            targets.append(np.fromiter(map(index.get, near_keys, itertools.repeat(-1)),
                                       dtype=np.int64, count=len(near_keys)))
            lps.append(np.asarray(near_lps, dtype=float))
            starts[i + 1] = len(near_keys)
    indptr = np.cumsum(np.array(starts, dtype=np.int64))
    targets = np.concatenate(targets) if targets else np.empty(0, dtype=np.int64)
    lps = np.concatenate(lps) if lps else np.empty(0)
    mine = np.fromiter(map(index.__getitem__, row_keys(visited)), dtype=np.int64,
                       count=len(visited))
    floor, expand = closure._levels
    return [_reach(indptr, targets, lps, mine[np.unique(rows)], float(floor), float(expand))
            for rows in per_chain]


@njit(cache=True, nogil=True)
def _reach(indptr, targets, lps, sources, floor, expand):
    # found_by_chain's traversal over numbered states: the sources, each state above the
    # floor one block from a state walked, and on from those within expand of the best;
    # sorted indices.
    n = indptr.shape[0] - 1
    mark = np.zeros(n, dtype=np.bool_)
    stack = np.empty(n, dtype=np.int64)
    top = 0
    for s in sources:
        if not mark[s]:
            mark[s] = True
            stack[top] = s
            top += 1
    while top > 0:
        top -= 1
        u = stack[top]
        for e in range(indptr[u], indptr[u + 1]):
            v = targets[e]
            if v >= 0 and lps[e] >= floor and not mark[v]:
                mark[v] = True
                if lps[e] >= expand:
                    stack[top] = v
                    top += 1
    return np.flatnonzero(mark)
