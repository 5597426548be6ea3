"""The chains' rounds: run them until the stopping rule holds, and score what they recorded.

:func:`run_rounds` advances the chains (``mcmc.ChainRun``) round by round (one round for a
fixed ``n_samples``), leaves out samples that provably hold no mass (restarting, once, a chain
stuck there), weighs what they found through the closure (:mod:`._closure`) and asks the
stopping rule (:mod:`bsi_sklearn.inference.stopping`) after each round; with ``trial=True`` it
gives up unless the rule holds after the first (the untempered round of
:func:`~bsi_sklearn.inference.mcmc.sample_posterior`). :func:`score_states` and
:func:`unique_states` score and count the states they recorded.
"""

import numpy as np

from bsi_sklearn._unique_rows import unique_rows
from bsi_sklearn.inference._chain_kernel import score_rows
from bsi_sklearn.inference._closure import Closure, found_by_chain, found_states
from bsi_sklearn.inference._negligible import common_burn_in, negligible_margin
from bsi_sklearn.inference._reach import visited_shares
from bsi_sklearn.inference.diagnostics import inclusion_rhat, too_diffuse
from bsi_sklearn.inference.stopping import inclusion_by_chain, should_stop

__all__ = ["unique_states", "score_states", "sweep_work", "run_rounds"]


def unique_states(states, counts, return_inverse=False):
    """Unique state rows (sorted canonically) and the number of samples of each.

    With ``return_inverse``, also the index of every input row among the unique rows.
    """
    if len(states) == 0 or states.shape[1] == 0:
        # Zero-width rows (empty template): every sample is the same hypothesis.
        out = states[:1], np.array([int(np.sum(counts))], dtype=np.int64)[: len(states[:1])]
        return (*out, np.zeros(len(states), dtype=np.int64)) if return_inverse else out
    first, inverse = unique_rows(states)
    total = np.bincount(inverse, weights=counts, minlength=len(first))
    out = states[first], total.astype(np.int64)
    return (*out, inverse) if return_inverse else out


def score_states(states, demos, model):
    """Exact unnormalised log posterior of every state row ``[tau, w1, parent]``."""
    return score_rows(np.ascontiguousarray(states), demos, model)


def sweep_work(demos, model):
    # One sweep of one replica, as sampling_count counts it: every candidate over every row.
    n_g, n = model.n_g, model.n
    return (n_g + n + n * (n + 1)) * demos.truth_t.shape[1]


def run_rounds(runs, plan, demos, model, n_jobs, verbose, *, budget_rungs=None,
               trial=False, done=0, report=False, closure=None, desc="MCMC sweeps"):
    # Run the chains round by round (one round for a fixed n_samples) until the stopping rule
    # holds; returns their results, the unique states visited with their sample counts, the
    # last round's chains' shares and the probabilities they index, as the stopping rule
    # counted them (None, None where it did not: one round, or a posterior too diffuse to
    # list), the states' exact log posteriors, the rounds' record and the closure's states.
    # `trial`: None unless the stopping rule holds after the first round. `budget_rungs`: the
    # rungs a chain's later rounds are counted with in the closure's budget (default: its own).
    # `done`: sweeps the runs have recorded already. `report`: one round is weighed as the
    # rounds of n_samples="auto" are (the closure's states join the support). `closure`: the
    # one to update (default: a new one, budgeted by the rounds after the first).
    from sklearn.utils.parallel import Parallel, delayed

    bar = None
    if verbose:
        from tqdm.auto import tqdm

        bar = tqdm(total=len(runs) * plan[-1], initial=len(runs) * done, desc=desc,
                   unit="sweep")
    scored = {}  # the exact log posterior of every state seen, by its row's bytes
    margin = negligible_margin(model.n_g, model.n)
    restarted = False
    record, near = [], None
    # What the chains may still do after the first round (sampling_count's count): a plateau
    # of ties found whole by the closure saves it.
    if closure is None:
        rungs = (sum(len(run.betas) for run in runs) if budget_rungs is None
                 else budget_rungs * len(runs))
        closure = Closure(demos, model, sampling_work=float(rungs) * (plan[-1] - plan[0])
                          * sweep_work(demos, model))
    # Chains are threads of this process (the kernels release the GIL), also when an outer
    # joblib backend such as dask distributes whole fits.
    with Parallel(n_jobs=n_jobs, backend="threading") as parallel:
        for total in plan:
            parallel(delayed(run.advance)(total - done) for run in runs)
            if bar is not None:
                bar.update(len(runs) * (total - done))
            done = total
            # Samples provably without mass (far below the best found) are burn-in; a chain
            # that stays there is restarted from the best state once, or left out
            # (:mod:`._negligible`).
            while True:
                results = [run.result() for run in runs]
                visited, counts, per_chain, visited_lp = _scored_record(results, scored,
                                                                        demos, model)
                skip, live = common_burn_in(per_chain, [r.counts for r in results],
                                            visited_lp, margin)
                if live.all() or restarted:
                    break
                # The chains left behind go on from the best state found, every chain's
                # record so far is burn-in, and the round is run again.
                best = visited[int(np.argmax(visited_lp))].astype(np.int64)
                runs = [run.discard() if ok else run.restarted_at(best)
                        for run, ok in zip(runs, live)]
                restarted = True
                parallel(delayed(run.advance)(total) for run in runs)
                if bar is not None:
                    bar.update(len(runs) * total)
            if skip or not live.all():
                results = [run.result(skip) for run, ok in zip(runs, live) if ok]
                visited, counts, per_chain, visited_lp = _scored_record(results, scored,
                                                                        demos, model)
            shares = probs = None
            if len(plan) == 1 and not report:
                break
            traces = np.stack([r.trace_lp for r in results])
            # They agree when each chain's share holds what they found together: what its
            # visited states lead to, or (past the closure's budget) what it reached, visited
            # or weighed one block away (:mod:`._reach`); a posterior too diffuse to list,
            # reported by the samples, when each clause's inclusion agrees across them (the
            # closure, which weighs states exactly, is then not updated: it says nothing).
            inclusion = sampled = first = None
            if too_diffuse(visited_lp, counts, traces)[0]:
                sampled = inclusion_rhat(visited, per_chain, [r.counts for r in results],
                                         model.n_g, model.n)
                stop, detail = should_stop(None, None, None, traces, sampled=sampled)
                record.append(dict(detail, n_samples=done))
                if stop:
                    break
                if trial:
                    return _closed(bar)
                continue
            # They stopped finding mass when the states first found late hold little: found
            # is visited, or weighed from a visited state and so in the support
            # (:mod:`._closure`). Reach alone would not do: a walk's new state is always one
            # block from its last, so every late state would count as reached early.
            first = np.full(len(visited), np.iinfo(np.int64).max)
            for r, rows in zip(results, per_chain):
                np.minimum.at(first, rows, np.cumsum(r.counts) - r.counts)
            near = closure.update(visited, visited_lp, first)
            if near is None:  # the closure is past its budget: the support cannot be listed
                shares, probs = visited_shares(visited, visited_lp, model, per_chain)
                inclusion = inclusion_by_chain(visited, probs, shares, model.n_g, model.n)
            else:
                probs, first, keys = found_states(visited, visited_lp, first, near)
                shares = found_by_chain(closure, visited, per_chain, keys)
            stop, detail = should_stop(shares, probs, first, traces, inclusion)
            record.append(dict(detail, n_samples=done))
            if stop:
                break
            if trial:
                return _closed(bar)
    _closed(bar)
    stopping = {"rounds": record, "stopped_early": done < plan[-1],
                "negligible_burn_in": int(skip),
                "restarted": restarted, "lost_chains": [int(k) for k in np.flatnonzero(~live)]}
    # What the support holds whole: the neighbours above a floor of the states the update that
    # found `near` traversed (none where no update ran, or once the closure is given up).
    return (results, visited, counts, (shares, probs), visited_lp, stopping, near, per_chain,
            closure.complete)


def _closed(bar):
    if bar is not None:
        bar.close()


def _scored_record(results, scored, demos, model):
    # The chains' unique visited states, their sample counts, each chain's record as indices
    # into them, and their exact log posteriors (scored once: ``scored`` caches by row bytes).
    visited, counts, row_state = unique_states(
        np.concatenate([r.states for r in results], axis=0),
        np.concatenate([r.counts for r in results]), return_inverse=True)
    new = [i for i in range(len(visited)) if visited[i].tobytes() not in scored]
    if new:
        lp_new = score_states(visited[new], demos, model)
        scored.update(zip((visited[i].tobytes() for i in new), lp_new.tolist()))
    visited_lp = np.array([scored[row.tobytes()] for row in visited])
    ends = np.cumsum([len(r.states) for r in results])
    return visited, counts, np.split(row_state, ends[:-1]), visited_lp
