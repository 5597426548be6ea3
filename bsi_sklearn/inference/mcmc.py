"""MCMC over (tau, W1, order structure): tempered Gibbs chains in numba, and their result.

Each chain runs a ladder of replicas at inverse temperatures ``1 = beta_0 > ... > beta_{R-1}``
(parallel tempering, :mod:`bsi_sklearn.inference._chain_kernel`): a sweep redraws every
coordinate of every replica by an exact Gibbs update of its block, each candidate weighted by
prior x likelihood^beta (:mod:`bsi_sklearn.inference._gibbs_moves`), then adjacent replicas
propose to swap; only the beta = 1 replica is recorded. Hot replicas cross the valleys between
modes that single-coordinate moves cannot (a valley of a few violated demonstrations costs
``beta x |log eps|`` each), and swaps hand what they find down the ladder. The burn-in is
that search (a pilot, after which the ladder keeps the rungs its swaps call for); the first
recorded round then runs on one rung and is kept where the stopping rule holds after it, the
ladder's rounds starting over otherwise (:mod:`bsi_sklearn.inference._rounds` runs them).

:func:`sample_posterior` runs the chains, scores every visited state exactly, and returns an
:class:`MCMCResult`: the reported posterior is the exact posterior restricted to the visited
states (plus the deterministic optimum of :func:`deterministic_optimum` when no chain visited
it), renormalised, and a dictionary of diagnostics (:mod:`bsi_sklearn.inference.diagnostics`).
A posterior too diffuse to list that way (its mass over far more states than the chains can
visit twice, :func:`~bsi_sklearn.inference.diagnostics.too_diffuse`) is reported by the
chains' sample frequencies instead.
"""

from typing import NamedTuple

import numpy as np

from bsi_sklearn._unique_rows import unique_rows
from bsi_sklearn.inference._chain_kernel import (
    ChainState,
    Demos,
    chain_kernel,
    make_buffers,
    make_loop,
    violation_rows,
)
from bsi_sklearn.inference._closure import CLOSURE_WORK, PER_SAMPLING, Closure
from bsi_sklearn.inference._consistent_start import consistent_start
from bsi_sklearn.inference._demo_moves import best_demo_move
from bsi_sklearn.inference._ladder import (
    PILOT_MIN,
    adapted_ladder,
    pilot_rejection,
    swap_tries,
    temperature_ladder,
)
from bsi_sklearn.inference._local_search import beam_search, complete_support
from bsi_sklearn.inference._negligible import negligible_margin
from bsi_sklearn.inference._reach import visited_shares
from bsi_sklearn.inference._rounds import run_rounds, score_states, sweep_work, unique_states
from bsi_sklearn.inference.diagnostics import (
    LISTING_TOL,
    MISSED_WARN,
    MODE_WARN,
    RHAT_WARN,
    half_inclusions,
    inclusion_rhat,
    listing_gap,
    missed_mass,
    split_rhat,
    too_diffuse,
    weighted_inclusion,
)
from bsi_sklearn.inference.stopping import FIRST_ROUND, MAX_SAMPLES, rounds
from bsi_sklearn.model.clauses import n_clauses, pack_rows
from bsi_sklearn.model.priors import draw_hypothesis, first_structure
from bsi_sklearn.model.state_layout import join_state, split_state, split_states

__all__ = ["Demos", "ChainResult", "MCMCResult", "ChainRun", "run_chain", "deduplicate_demos",
           "score_states", "unique_states", "temperature_ladder", "deterministic_optimum",
           "sampling_count", "sample_posterior"]

#: Hypotheses the beam search of :func:`deterministic_optimum` keeps at every step.
BEAM_WIDTH = 8


class ChainResult(NamedTuple):
    """What one chain returns (:func:`run_chain`)."""

    states: np.ndarray      # recorded rows [tau (n_g), w1 (n), parent (n)], run-length encoded
    counts: np.ndarray      # samples each row stands for
    trace_lp: np.ndarray    # log posterior after every recorded sweep
    move_rate: float        # fraction of the beta = 1 replica's block updates that moved it
    n_updates: int          # block updates of all replicas
    swap_rate: np.ndarray   # (R - 1,) accepted fraction of swaps between rungs k and k + 1
    n_burned: int           # sweeps discarded: burn_in and the extension up to the target


class MCMCResult(NamedTuple):
    """The reported posterior of :func:`sample_posterior` and its diagnostics.

    ``structures`` (parent arrays), ``tau_masks``, ``w1_masks`` and ``probabilities`` list the
    specifications by decreasing probability, as :class:`bsi_sklearn.Posterior` takes them;
    ``map_index`` is the position of the most probable specification found (0 unless the
    posterior is reported by its samples, where it may be sampled less often than others, or
    never: then it is listed with probability 0).
    """

    structures: np.ndarray  # (H, n) int64
    tau_masks: np.ndarray   # (H, n_g) bool
    w1_masks: np.ndarray    # (H, n) bool
    probabilities: np.ndarray
    diagnostics: dict
    violations: np.ndarray  # (H,) misclassified demonstrations, with a flip prior; else None
    map_index: int = 0


def deduplicate_demos(truth, y01):
    """Collapse demonstrations with identical clause-truth rows into weighted unique rows.

    Returns
    -------
    Demos
        ``truth_t`` (n_clauses, n_unique) uint8, the transposed unique rows (clause-major for
        the kernel's inner loops); ``w_pos`` / ``w_neg`` (n_unique,) float64, the numbers of
        acceptable / unacceptable demonstrations behind every unique row; their sums.
    """
    first, inverse = unique_rows(truth)
    rows = truth[first]
    w_pos = np.bincount(inverse, weights=(y01 == 1).astype(float), minlength=len(rows))
    w_neg = np.bincount(inverse, weights=(y01 == 0).astype(float), minlength=len(rows))
    truth_t = np.ascontiguousarray(rows.T)
    # Whole-number weights: their sums are exact in any order.
    return Demos(truth_t, np.ascontiguousarray(w_pos, dtype=np.float64),
                 np.ascontiguousarray(w_neg, dtype=np.float64), float(w_pos.sum()),
                 float(w_neg.sum()), pack_rows(truth_t), _planes(w_pos), _planes(w_neg))


def _planes(weights):
    # Bit-plane k of whole-number weights, packed: a weighted count is a sum of popcounts.
    # No planes when every weight is 0 (no unacceptable demonstrations): nothing to count.
    w = weights.astype(np.int64)
    n_planes = int(w.max(initial=0)).bit_length()
    return pack_rows(((w[None, :] >> np.arange(n_planes)[:, None]) & 1).astype(np.uint8))


def deterministic_optimum(demos, model, width=BEAM_WIDTH):
    """A cheap optimum of the posterior, found without random numbers.

    Beam search (:mod:`bsi_sklearn.inference._local_search`) from the hypothesis without
    clauses (and the first order structure of the prior's support): every step scores, exactly,
    every hypothesis one Gibbs block away from those in the beam (one global bit; one subtask's
    place with its eventual bit) and keeps the ``width`` best, until the beam no longer
    changes. A second beam starts from every clause the acceptable demonstrations keep
    (:mod:`bsi_sklearn.inference._consistent_start`), which reaches the size principle's
    optimum where single blocks from the empty hypothesis stop short; its result is taken only
    when strictly more probable. From the better, moves of many clauses at once about one
    acceptable demonstration (keep it, or give it up: :mod:`bsi_sklearn.inference._demo_moves`)
    are scored exactly, and pairs of them from the ``width`` best single ones where none
    beats it; while the best does, the beam search continues from there.
    Returns ``(row, log posterior)`` with ``row`` laid out as the sampler's states,
    ``[tau, w1, parent]`` (int16).
    """
    n_g, n = model.n_g, model.n
    start = join_state(np.zeros(n_g), np.zeros(n), first_structure(model))
    max_steps = 4 * n_clauses(n_g, n) + 10
    row, lp = beam_search(start[None, :], demos, model, int(width), max_steps)
    seeded = consistent_start(demos, model)
    if not np.array_equal(seeded, start):
        row_s, lp_s = beam_search(seeded[None, :], demos, model, int(width), max_steps)
        if lp_s > lp:
            row, lp = row_s, lp_s
    # Each round strictly improves the log posterior, so no state returns and the rounds
    # end; the cap (one a deduplicated demonstration, and one) only bounds the time.
    for _ in range(len(demos.w_pos) + 1):
        move, move_lp = best_demo_move(row, lp, demos, model, int(width))
        if not move_lp > lp:
            break
        row, lp = beam_search(move[None, :], demos, model, int(width), max_steps)
    return row.astype(np.int16), float(lp)


class ChainRun:
    """One chain that can be run in several calls (the rounds of ``n_samples="auto"``).

    Holds the replicas' state, the kernel's buffers and :class:`~._chain_kernel.ChainLoop`,
    and the generator: :meth:`advance` resumes exactly where the last call stopped, so that
    rounds of 500 and 500 sweeps record what one call of 1,000 would.
    """

    def __init__(self, seed, demos, model, betas=None, start=None, *, burn_in=0,
                 target=-np.inf, max_extra=0):
        self.betas = (np.ones(1) if betas is None
                      else np.ascontiguousarray(betas, dtype=np.float64))
        self.demos, self.model = demos, model
        self.burn_in, self.target, self.max_extra = int(burn_in), float(target), int(max_extra)
        self.rng = np.random.default_rng(seed)  # a Generator is taken as it is
        self.pilot_sweeps = self.pilot_updates = 0  # what a pilot did before (ladder_from)
        n_g, n, n_rungs = model.n_g, model.n, len(self.betas)
        if start is None:
            draws = [draw_hypothesis(model, self.rng) for _ in range(n_rungs)]
        elif isinstance(start, ChainState):  # one hypothesis per rung
            draws = [(start.tau[r], start.w1[r], start.parent[r]) for r in range(n_rungs)]
        else:
            start = np.asarray(start, dtype=np.int64)
            draws = [split_state(start, n_g, n)] * n_rungs
        # The kernel's state and scratch buffers live here, for every call (see _unmanaged).
        self.state = ChainState(*(
            np.ascontiguousarray(np.stack([d[i] for d in draws]), dtype=np.int64)
            .reshape(n_rungs, -1) for i in range(3)))
        self.bufs = make_buffers(n_g, n, demos.truth_t.shape[1], n_rungs)
        self.loop = make_loop(n_rungs)
        self.states, self.counts, self.traces = [], [], []

    def ladder_from(self, betas, **params):
        """A chain on the ladder ``betas`` (``params``: ``__init__``'s) going on from this one.

        Each rung starts from this pilot's replica on the nearest rung (in log beta), with its
        generator; the pilot's sweeps count as burned, its block updates as work.
        """
        sweep, _, _, _, updates, _ = self.loop.counters.tolist()
        old = np.log(self.betas)
        replicas = self.loop.slot[[int(np.argmin(np.abs(old - b))) for b in np.log(betas)]]
        start = ChainState(*(np.ascontiguousarray(a[replicas]) for a in self.state))
        run = ChainRun(self.rng, self.demos, self.model, betas, start, **params)
        run.pilot_sweeps = self.pilot_sweeps + int(sweep)
        run.pilot_updates = self.pilot_updates + int(updates) * len(self.betas)
        return run

    def restarted_at(self, row, betas=None):
        """A chain going on from ``row`` (every rung), with this one's generator.

        On the ladder ``betas`` (default: this one's). Its sweeps so far count as burned; its
        record is dropped.
        """
        sweep, _, _, _, updates, _ = self.loop.counters.tolist()
        run = ChainRun(self.rng, self.demos, self.model,
                       self.betas if betas is None else betas, row, burn_in=0)
        run.pilot_sweeps = self.pilot_sweeps + int(sweep)
        run.pilot_updates = self.pilot_updates + int(updates) * len(self.betas)
        return run

    def absorb(self, other):
        """Count ``other``'s sweeps as this chain's burn-in and its block updates as work."""
        sweep, _, _, _, updates, _ = other.loop.counters.tolist()
        self.pilot_sweeps += int(sweep)
        self.pilot_updates += int(updates) * len(other.betas)
        return self

    def coldest(self):
        """The beta = 1 replica's hypothesis now, as one row (int64)."""
        r = int(self.loop.slot[0])
        return join_state(self.state.tau[r], self.state.w1[r], self.state.parent[r])

    def discard(self):
        """Drop the record so far; its samples count as burned."""
        self.pilot_sweeps += int(sum(int(np.sum(c)) for c in self.counts))
        self.states, self.counts, self.traces = [], [], []
        return self

    def advance(self, n_samples):
        """Record ``n_samples`` more sweeps (after the burn-in, on the first call)."""
        states, counts, trace_lp = chain_kernel(
            self.state, self.demos, self.model, self.bufs, self.betas, self.rng, self.loop,
            int(n_samples), self.burn_in, self.target, self.max_extra)
        self.states.append(states)
        self.counts.append(counts)
        self.traces.append(trace_lp)
        return self

    def result(self, skip=0):
        """The chain's :class:`ChainResult` so far, its first ``skip`` samples burned."""
        sweep, burned, _, moved, updates, _ = self.loop.counters.tolist()
        tries = swap_tries(sweep, len(self.loop.swaps))
        states, counts = np.concatenate(self.states), np.concatenate(self.counts)
        traces = np.concatenate(self.traces)
        if skip:  # drop whole records before the skip, and the skipped part of the one across
            ends = np.cumsum(counts)
            cut = int(np.searchsorted(ends, skip, side="right"))
            states, counts = states[cut:], counts[cut:].copy()
            if len(counts):
                counts[0] = ends[cut] - skip
            traces = traces[skip:]
        return ChainResult(states, counts, traces, moved / max(updates, 1),
                           int(updates) * len(self.betas) + self.pilot_updates,
                           self.loop.swaps / np.maximum(tries, 1),
                           burned + self.pilot_sweeps + int(skip))


def run_chain(seed, demos, model, n_samples, burn_in, betas=None, start=None, *,
              target=-np.inf, max_extra=0):
    """Run one chain; every replica starts from ``start``, or its own draw of the prior.

    Parameters
    ----------
    seed : int
        Seed of the chain's ``numpy.random.Generator`` (prior draws and every move).
    demos : Demos
        Deduplicated clause truth and label weights (:func:`deduplicate_demos`).
    model : Model
        The model bundle (:func:`bsi_sklearn.model.make_model`).
    n_samples, burn_in : int
        Sweeps recorded, and sweeps discarded first.
    betas : array-like of float, default=None
        The ladder (:func:`temperature_ladder`), ``betas[0] = 1``; ``None``: one replica.

    Returns
    -------
    ChainResult
    """
    return ChainRun(seed, demos, model, betas, start, burn_in=burn_in, target=target,
                    max_extra=max_extra).advance(n_samples).result()


def sampling_count(truth, y01, model, *, n_chains, n_samples, burn_in, n_temperatures="auto"):
    """How much work :func:`sample_posterior` may do: candidate evaluations x rows.

    Every sweep of every replica of every chain weighs the ``n_g + n`` inclusion bits and, for
    each of the ``n`` subtasks, its ``n + 1`` places (:mod:`bsi_sklearn.inference._gibbs_moves`),
    each candidate over every unique demonstration row; ``burn_in + n_samples`` sweeps at least
    (a chain that has not reached the optimum's neighbourhood runs longer; ``"auto"`` counts its
    most, 10,000, where it may stop sooner), on the default ladder's rungs (after the pilot,
    the adapted ladder has as many or fewer, and the replicas that do not move cost less than
    counted: the sampling this count stands for is what it costs before adaptation, a bound
    that does not depend on a pilot's draws). A count of the data
    and the parameters only, never of timing: ``inference="auto"`` compares it with the exact
    engine's work count (``BSIClassifier``).

    Returns
    -------
    count : float
    """
    demos = deduplicate_demos(truth, y01)
    n_samples = MAX_SAMPLES if n_samples == "auto" else n_samples  # at most
    rungs = len(temperature_ladder(demos, model, n_temperatures))
    return float(n_chains) * (int(n_samples) + int(burn_in)) * rungs * sweep_work(demos, model)


def _after_pilot(pilots, betas, demos, model, chain):
    # Each pilot goes on on the adapted ladder from its replicas (ChainRun.ladder_from),
    # unless its beta = 1 replica ended more than the negligible margin below the best
    # pilot's: then from that replica's state on every rung (restarted_at). Its samples from
    # where it is would provably hold no mass, and the round would be run again once they did
    # (run_rounds' restart: on event logs, chains stuck thousands of nats below another's
    # mode). Returns the runs and the restarted chains' indices.
    rows = np.stack([p.coldest() for p in pilots])
    lp = score_states(rows, demos, model)
    floor = lp.max() - negligible_margin(model.n_g, model.n)
    best = rows[int(np.argmax(lp))]
    runs = [p.ladder_from(betas, burn_in=0, **chain) if v >= floor
            else p.restarted_at(best, betas) for p, v in zip(pilots, lp.tolist())]
    return runs, [int(i) for i in np.flatnonzero(lp < floor)]


def _untempered_first(runs, plan, betas, demos, model, chain, n_jobs, verbose):
    # Tempering finds modes; once the pilot has searched, the chains may not need it. The
    # first round runs untempered from the pilot's beta = 1 replicas, and is kept if the
    # stopping rule holds after it (a fixed n_samples: the rest of it runs on one rung);
    # otherwise the rounds start over on the adapted ladder, the untempered round counted as
    # burn-in. On a plateau of weakly determined clauses (100 activities) every rung samples
    # nearly the cold posterior, and the swaps only slow the chains' agreement down (4,000
    # tempered sweeps against 500). Returns run_rounds' result (None where the ladder's
    # rounds are to run), the runs and the ladder for them, and whether the round was kept.
    if len(plan) == 1 and plan[0] <= FIRST_ROUND:  # no room for a round before the record
        return None, runs, betas, False
    trial = [run.ladder_from(np.ones(1), burn_in=0, **chain) for run in runs]
    closure = None
    if len(plan) == 1:
        # A fixed n_samples is recorded whatever the closure finds: it may spend about what
        # the rungs it saves would have cost (a quarter more on ties), not its own budget (a
        # flat posterior of 2.4e9 dinner-table specifications: 0.65 s a fit tempered, 4.2 s
        # with the closure's own budget).
        saved = (len(betas) - 1) * plan[0] * len(runs) * sweep_work(demos, model)
        closure = Closure(demos, model, max_work=min(CLOSURE_WORK, PER_SAMPLING * saved),
                          sampling_work=saved)
    out = run_rounds(trial, plan if len(plan) > 1 else [FIRST_ROUND, plan[0]], demos, model,
                     n_jobs, verbose, budget_rungs=len(betas), trial=True, closure=closure,
                     desc="MCMC sweeps (one rung)")
    if out is None:
        return None, [run.absorb(t) for run, t in zip(runs, trial)], betas, False
    if len(plan) == 1:
        # Weighed as the rounds are: on one rung, the closure's states complete plateaus of
        # interchangeable subtasks that tempered chains would cross and untempered ones share
        # out between them.
        out = run_rounds(trial, plan, demos, model, n_jobs, verbose, done=FIRST_ROUND,
                         report=True, closure=closure, desc="MCMC sweeps (one rung)")
    return out, trial, np.ones(1), True


def sample_posterior(truth, y01, model, seeds, *, n_samples="auto", burn_in=100,
                     n_temperatures="auto", n_jobs=None, verbose=0):
    """The MCMC posterior: tempered chains, the states they found scored exactly.

    Every chain (every replica of its ladder) starts from the deterministic optimum
    (:func:`deterministic_optimum`): a beam search finds the best basin that single-coordinate
    moves from the hypothesis without clauses often cannot reach on large problems, and the
    hot replicas leave it at once. Burn-in lasts ``burn_in`` sweeps and then, for at most
    ``burn_in`` more, until the chain's log posterior is within ``log 20`` of the optimum's
    (the first ``burn_in`` on the default ladder: a pilot that adapts it). A chain whose
    samples all lie so far below the best state found that they provably hold under 1e-17 of
    the mass (:mod:`bsi_sklearn.inference._negligible`: modes apart by misclassified
    demonstrations, thousands of nats on event logs) goes on from that state, once, after
    which the round is run again and the record so far is burn-in for every chain
    (``diagnostics["stopping"]["restarted"]``); a chain whose beta = 1 replica ends the pilot
    that far below the best pilot's goes on from that one's state before anything is recorded
    (``diagnostics["ladder"]["restarted"]``); samples still below are burned alike, and a
    chain that stays there is left out (``["lost_chains"]``). The reported
    posterior is the exact posterior restricted to the states the chains recorded, the
    optimum, the neighbours of the recorded states that the stopping rule counted as found
    (:mod:`bsi_sklearn.inference._closure`; ``n_samples="auto"``), and the one-block
    neighbours of the most probable of them (where the posterior is flat, states each too
    improbable to be visited add up), renormalised. Where the visited states, so reweighted,
    lie on average more than log 20 above the chains' own log posterior (``typical_gap``:
    many clauses the data leave undetermined, each near its prior inclusion, spread the mass
    over far more states than the chains visit, each visited about once: ``unseen_mass``, the
    share of samples whose state was sampled once, above ``MISSED_WARN``), that restriction
    would pile the mass onto the most probable states found; the probabilities are then the
    sample frequencies of the visited states (``sampled``; so too where the samples leave
    more than ``MISSED_WARN`` unseen and the restriction fails its own check, a chain missing
    more than ``MISSED_WARN`` of the mass found while the chains agree on every clause's
    inclusion, or does not report what they sample, a clause's inclusion under it beyond the
    samples' noise from theirs, ``listing_gap`` above ``LISTING_TOL``), the
    most often sampled first (ties: the most probable); the most probable state found (the
    MAP, ``map_index``) is listed too, with probability 0 if never sampled: in so flat a
    posterior every state's mass is tiny, and the most often sampled one is no better an
    estimate of the MAP than any other visited once more by chance.

    Parameters
    ----------
    truth : ndarray of shape (n_demos, n_clauses)
        Clause truth (:func:`bsi_sklearn.model.clauses.clause_truth`).
    y01 : ndarray of shape (n_demos,)
        Labels, 1 acceptable and 0 not.
    model : Model
    seeds : sequence of int
        One chain per seed; results depend on the seeds only, not on ``n_jobs``.
    n_samples : int or "auto", default="auto"
        Sweeps recorded per chain; ``"auto"``: in doubling rounds, until the chains agree and
        stop finding mass (:mod:`bsi_sklearn.inference.stopping`), at most 10,000.
    burn_in : int, default=100
        Sweeps discarded first (and the extension).
    n_temperatures : "auto" or int, default="auto"
        Rungs of every chain's ladder (:func:`temperature_ladder`); ``"auto"`` with a
        burn-in of at least ``PILOT_MIN`` sweeps: the burn-in is a pilot on the default
        ladder, which is then adapted (:func:`~._ladder.adapted_ladder`). The first round
        (``FIRST_ROUND`` sweeps) then runs on one rung and is kept where the stopping rule
        holds after it (else the rounds start over on the adapted ladder); a fixed
        ``n_samples`` above it records the rest on the ladder so chosen.
    n_jobs : int, default=None
        Chains run in threads of this process (the kernels release the GIL).
    verbose : int, default=0
        Progress bar over the chains' sweeps when > 0.

    Returns
    -------
    MCMCResult
        The specifications by decreasing probability; ``diagnostics`` holds ``rhat``,
        ``max_missed_mass``, ``optimum_gap`` and the rest (see
        :class:`bsi_sklearn.BSIClassifier`).
    """
    n_g, n = model.n_g, model.n
    demos = deduplicate_demos(truth, y01)
    betas = temperature_ladder(demos, model, n_temperatures)
    optimum, optimum_lp = deterministic_optimum(demos, model)
    plan = rounds() if n_samples == "auto" else [int(n_samples)]
    # The extension lets a chain that the pilot's swaps left below the optimum's level climb
    # back, for as long again as the burn-in: a chain still below after that samples a
    # posterior whose typical states lie far below its mode (where a thousand weakly determined
    # clauses combine, 56 nats below at 100 activities), and burning on would last forever.
    chain = dict(target=optimum_lp - MODE_WARN, max_extra=int(burn_in))
    ladder = None
    if n_temperatures == "auto" and len(betas) > 2 and int(burn_in) >= PILOT_MIN:
        # The burn-in is the pilot: it runs on the default ladder, which is then adapted.
        pilots = [ChainRun(int(seed), demos, model, betas, optimum) for seed in seeds]
        rejection = pilot_rejection(pilots, int(burn_in), n_jobs)
        ladder = {"default_betas": betas, "pilot_rejection": rejection,
                  "barrier": float(rejection.sum())}
        betas = ladder["adapted_betas"] = adapted_ladder(betas, rejection)
        runs, ladder["restarted"] = _after_pilot(pilots, betas, demos, model, chain)
    else:
        runs = [ChainRun(int(seed), demos, model, betas, optimum, burn_in=int(burn_in),
                         **chain) for seed in seeds]
    out = None
    if ladder is not None:
        out, runs, betas, ladder["untempered"] = _untempered_first(
            runs, plan, betas, demos, model, chain, n_jobs, verbose)
    if out is None:
        out = run_rounds(runs, plan, demos, model, n_jobs, verbose)
    (results, visited, counts, counted, visited_lp, stopping, near, per_chain,
     complete) = out
    # The support: the visited states, the optimum, what the last round found one block from
    # the visited states, and the neighbourhood of the most probable.
    support = np.concatenate([visited, optimum[None, :]])
    support_lp = np.concatenate([visited_lp, [optimum_lp]])
    counts = np.concatenate([counts, [0]])
    if near is not None:
        support = np.concatenate([support, near[0]])
        support_lp = np.concatenate([support_lp, near[1]])
        counts = np.concatenate([counts, np.zeros(len(near[0]), dtype=np.int64)])
    extra, extra_lp = complete_support(support, support_lp, demos, model, complete)
    uniq, counts, inverse = unique_states(
        np.concatenate([support, extra]),
        np.concatenate([counts, np.zeros(len(extra), dtype=np.int64)]), return_inverse=True)
    scores = np.empty(len(uniq))
    scores[inverse] = np.concatenate([support_lp, extra_lp])
    # Sort by decreasing posterior; ties keep np.unique's canonical order.
    order = np.argsort(-scores, kind="stable")
    uniq, counts, scores = uniq[order], counts[order], scores[order]
    traces = np.stack([r.trace_lp for r in results])
    sampled, gap, unseen = too_diffuse(scores, counts, traces)
    # The listing: the exact posterior restricted to the support.
    probs = np.exp(scores - scores.max())
    probs /= probs.sum()
    listed_gap = 0.0
    halves = (half_inclusions(visited, per_chain, [r.counts for r in results], n_g, n)
              if not sampled and unseen > MISSED_WARN and near is None else None)
    if halves is not None:
        # The listing must report what the chains sample: asked where it may miss mass and no
        # closure completed it (a fixed n_samples, or the closure past its budget; within
        # it, the rounds stop once the states first found late hold at most STOP_LATE).
        listed = weighted_inclusion(uniq, probs[None, :], n_g, n)[0, :n_clauses(n_g, n)]
        listed_gap = listing_gap(listed, halves[0])
        sampled = listed_gap > LISTING_TOL
    if sampled:
        missed = np.full(len(results), np.nan)  # weighs states exactly: says nothing here
    else:
        shares, found = counted
        if shares is None:  # the last round's shares were not counted (one round, or sampled)
            shares, found = visited_shares(visited, visited_lp, model, per_chain)
        missed = missed_mass(shares, found)  # as the stopping rule counted it
    # Where the restricted posterior fails its own check (a chain never reached much of the
    # mass the others found) and the samples say the states found miss mass too (many
    # clauses weakly determined, the closure past its budget), the samples report the
    # posterior if the chains agree on every clause's inclusion.
    inclusion = None
    if sampled or (missed.max() > MISSED_WARN and unseen > MISSED_WARN):
        # The last round's stopping rule weighed it on these very samples where it reported
        # them by their samples.
        inclusion = (stopping["rounds"][-1].get("inclusion_rhat") if stopping["rounds"]
                     else None)
        if inclusion is None:
            inclusion = inclusion_rhat(visited, per_chain, [r.counts for r in results], n_g, n)
        sampled = sampled or bool(inclusion <= RHAT_WARN)
    if sampled:
        # Too diffuse to list: restricted to the states found, the posterior would pile onto
        # the most probable of them, so the samples report it: the visited states, the most
        # often sampled first (ties: the most probable). The MAP (scores are sorted: row 0)
        # stays listed, last if never sampled.
        keep = np.flatnonzero((counts > 0) | (np.arange(len(counts)) == 0))
        keep = keep[np.lexsort((-scores[keep], -counts[keep]))]
        map_index = int(np.flatnonzero(keep == 0)[0])
        uniq, counts, scores = uniq[keep], counts[keep], scores[keep]
        probs = counts / counts.sum()
    else:
        map_index = 0
    moves = np.array([r.move_rate for r in results])
    best_visited = float(visited_lp.max())
    diagnostics = {
        "missed_mass_per_chain": missed,
        "max_missed_mass": float(missed.max()),
        "rhat": split_rhat(traces),
        "optimum_log_posterior": optimum_lp,
        "best_visited_log_posterior": best_visited,
        "optimum_gap": optimum_lp - best_visited,
        "acceptance_rate": float(moves.mean()),
        "acceptance_rate_per_chain": moves,
        "betas": betas,
        "ladder": ladder,
        "swap_rate": np.stack([r.swap_rate for r in results]),
        "burn_in_per_chain": np.array([r.n_burned for r in results]),
        "n_updates": int(sum(r.n_updates for r in results)),
        "n_chains": len(seeds),
        "n_samples": len(traces[0]) if len(traces) else 0,
        "stopping": stopping,
        "burn_in": int(burn_in),
        "n_visited": len(visited),
        "n_added": len(uniq) - len(visited),
        "typical_gap": gap,
        "unseen_mass": unseen,
        "listing_gap": listed_gap,
        "sampled": bool(sampled),
        "inclusion_rhat": inclusion if sampled else None,
        "sample_frequencies": counts / counts.sum(),
        "log_posterior_traces": traces,
        "seeds": np.asarray(seeds),
    }
    # The flip rate's posterior needs each specification's misclassified demonstrations.
    violations = (violation_rows(np.ascontiguousarray(uniq, dtype=np.int64), demos, model)
                  if model.flip_a > 0 else None)
    tau, w1, parent = split_states(uniq, n_g, n)
    return MCMCResult(parent.astype(np.int64), tau.astype(bool), w1.astype(bool), probs,
                      diagnostics, violations, map_index)
