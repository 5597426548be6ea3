"""The one way into inference: the engine policy, :func:`infer`, and the result it returns.

:class:`bsi_sklearn.BSIClassifier` validates its input, resolves the roles, computes the clause
truth and calls :func:`infer` with an :class:`InferencePolicy` built from its parameters. Which
engine runs, how much exact work ``"auto"`` allows before it samples, what the refusal of
``"exact"`` says, the chains' seeds and the convergence warnings are decided here, once. Both
engines' answers come back as one :class:`InferenceResult`, which
:meth:`bsi_sklearn.Posterior.from_result` turns into a posterior.
"""

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from sklearn.exceptions import ConvergenceWarning
from sklearn.utils import check_random_state

from bsi_sklearn.data.inferred_roles import warn_all_roles
from bsi_sklearn.inference.auto_budget import AUTO_EXACT_BYTES, auto_work_budget
from bsi_sklearn.inference.diagnostics import disagreement_problems
from bsi_sklearn.inference.exact import (
    MAX_BYTES,
    ExactWorkExceeded,
    exact_posterior,
    exact_refusal,
)
from bsi_sklearn.inference.mcmc import sample_posterior
from bsi_sklearn.model.bundle import describe_globals
from bsi_sklearn.model.likelihood import flip_rate_posterior
from bsi_sklearn.model.priors import count_hypotheses, format_count

__all__ = ["InferencePolicy", "InferenceResult", "infer", "warn_disagreement"]

# Counted from infer: infer (1), the estimator's _fit (2), fit (3), the user's call (4).
_STACKLEVEL = 4


@dataclass(frozen=True)
class InferencePolicy:
    """How to infer: the estimator's engine parameters (``BSIClassifier``'s, same meaning).

    ``prior`` is the prior's name (the support's size and the messages name it);
    ``warn_all_roles`` says that every proposition was put in every role by default, which the
    estimator warns about when the support is sampled under ``"auto"``.
    """

    inference: str = "auto"
    prior: str = "sets_of_chains"
    max_exact_hypotheses: Any = None
    tol: float = 1e-9
    n_chains: int = 4
    n_samples: Any = "auto"
    burn_in: int = 1000
    n_temperatures: Any = "auto"
    n_jobs: Any = None
    verbose: int = 0
    random_state: Any = None
    warn_all_roles: bool = False


@dataclass(frozen=True)
class InferenceResult:
    """What :func:`infer` returns, whichever engine ran.

    Attributes
    ----------
    engine : {"exact", "mcmc"}
    structures, tau_masks, w1_masks : ndarray
        The listed specifications, by decreasing probability: ``(H, n)`` parent arrays and the
        ``(H, n_g)`` and ``(H, n)`` masks of their ``G`` and ``F`` clauses.
    probabilities : ndarray (H,)
        Normalised over the listed specifications.
    clause_marginals : ndarray or None
        Exact clause inclusion probabilities over the whole support (exact engine); ``None``:
        computed from the listed specifications.
    dropped_mass : float
        Posterior mass left out of the listing (exact engine with ``tol``); 0 for MCMC.
    violations : ndarray (H,) or None
        Misclassified training demonstrations of each listed specification, where the engine
        counted them (the sampler with a flip prior); ``None``: not counted.
    violation_counts, violation_weights : ndarray
        The distribution of the number of misclassified demonstrations over the posterior
        (exact engine: over the whole support), what the flip rate's posterior mixes.
    diagnostics : dict or None
        The sampler's diagnostics (``mcmc_diagnostics_``); ``None`` for exact.
    n_hypotheses : int or float
        Size of the prior's support.
    map_index : int
        Position in the listing of the most probable specification found: 0, except for a
        posterior reported by its samples (``diagnostics["sampled"]``), listed by how often
        each specification was sampled.
    """

    engine: str
    structures: np.ndarray
    tau_masks: np.ndarray
    w1_masks: np.ndarray
    probabilities: np.ndarray
    clause_marginals: Any
    dropped_mass: float
    violations: Any
    violation_counts: np.ndarray
    violation_weights: np.ndarray
    diagnostics: Any
    n_hypotheses: Any
    map_index: int = 0

    def flip_rate(self, n_demos, flip_prior):
        """The flip rate's posterior mean and 95 % interval (``None``s without a flip prior)."""
        return flip_rate_posterior(self.violation_counts, self.violation_weights, n_demos,
                                   flip_prior)


def infer(truth, y01, model, policy):
    """The posterior over specifications of a model given the clause truth and the labels.

    Parameters
    ----------
    truth : ndarray (n_demos, n_clauses)
        Clause truth (:func:`bsi_sklearn.model.clauses.clause_truth`).
    y01 : ndarray (n_demos,)
        Labels in {0, 1}.
    model : Model
        The prior and the likelihood (:func:`bsi_sklearn.model.make_model`).
    policy : InferencePolicy

    Returns
    -------
    result : InferenceResult

    Raises
    ------
    ValueError
        ``inference="exact"`` over ``max_exact_hypotheses``, or over the exact engine's
        memory limit: the message names the size and the way out.
    """
    n_hyp = count_hypotheses(policy.prior, model.n_g, model.n)
    engine, work = policy.inference, None
    cap = policy.max_exact_hypotheses
    over_cap = cap is not None and n_hyp > cap
    if engine == "auto":
        # The exact engine's own work count decides, whatever the support's size.
        engine = "mcmc" if over_cap else "exact"
        work = auto_work_budget(truth, y01, model, n_chains=int(policy.n_chains),
                                n_samples=policy.n_samples, burn_in=int(policy.burn_in),
                                n_temperatures=policy.n_temperatures)
    elif engine == "exact" and over_cap:
        raise ValueError(
            f"inference='exact' needs {n_hyp:,} hypotheses ({describe_globals(model)}, "
            f"{model.n} subtasks, prior={policy.prior!r}), above max_exact_hypotheses="
            f"{cap:,}; raise max_exact_hypotheses or use 'mcmc'")
    if engine == "exact":
        try:
            return _exact(truth, y01, model, policy, work, n_hyp)
        except ExactWorkExceeded as exc:
            if policy.inference == "exact":  # only the memory limit stops it: say so
                raise exact_refusal(exc, model, n_hyp, policy.prior) from exc
            # "auto": its budget or its memory is spent, sample
    if policy.inference == "auto" and policy.warn_all_roles:
        warn_all_roles(model.n_g, format_count(n_hyp), over_cap, stacklevel=_STACKLEVEL)
    result = _mcmc(truth, y01, model, policy, n_hyp)
    warn_disagreement(result.diagnostics, policy, n_hyp, stacklevel=_STACKLEVEL)
    return result


def warn_disagreement(diagnostics, policy, n_hyp, stacklevel=2):
    """ConvergenceWarnings: a better optimum than the chains found, chains that disagree."""
    now = ("'auto', at most 10,000" if policy.n_samples == "auto"
           else f"{policy.n_samples:,}")
    advice = (f"Increase n_samples (now {now}) or n_chains (now "
              f"{policy.n_chains}), or restrict the roles (global_candidates, subtasks, "
              f"conditions) to shrink the support ({format_count(n_hyp)} hypotheses).")
    for message in disagreement_problems(diagnostics):
        warnings.warn(f"{message} {advice}", ConvergenceWarning, stacklevel=stacklevel + 1)


def _exact(truth, y01, model, policy, work, n_hyp):
    max_bytes = AUTO_EXACT_BYTES if policy.inference == "auto" else MAX_BYTES
    res = exact_posterior(truth, y01, model, tol=float(policy.tol), max_work=work,
                          max_bytes=max_bytes)
    probs = np.exp(res.log_prob) / np.exp(res.log_prob).sum()
    # The engine counts misclassified demonstrations by mass over the whole support, not per
    # listed formula.
    return InferenceResult(
        engine="exact", structures=res.structures, tau_masks=res.tau_masks,
        w1_masks=res.w1_masks, probabilities=probs, clause_marginals=res.clause_marginals,
        dropped_mass=res.dropped_mass, violations=None,
        violation_counts=np.arange(len(res.violation_mass)),
        violation_weights=res.violation_mass, diagnostics=None, n_hypotheses=n_hyp)


def _mcmc(truth, y01, model, policy, n_hyp):
    rng = check_random_state(policy.random_state)
    seeds = rng.randint(np.iinfo(np.int32).max, size=policy.n_chains)
    res = sample_posterior(truth, y01, model, seeds, n_samples=policy.n_samples,
                           burn_in=int(policy.burn_in), n_temperatures=policy.n_temperatures,
                           n_jobs=policy.n_jobs, verbose=policy.verbose)
    return InferenceResult(
        engine="mcmc", structures=res.structures, tau_masks=res.tau_masks,
        w1_masks=res.w1_masks, probabilities=res.probabilities, clause_marginals=None,
        dropped_mass=0.0, violations=res.violations, violation_counts=res.violations,
        violation_weights=res.probabilities, diagnostics=res.diagnostics,
        n_hypotheses=n_hyp, map_index=res.map_index)
