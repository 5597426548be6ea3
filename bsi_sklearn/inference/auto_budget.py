"""How much exact work ``inference="auto"`` allows before it samples instead.

At least :data:`AUTO_EXACT_WORK` (about a second on this project's 2-core reference machine)
and, where sampling would cost more, as much as the MCMC fallback would: its count
(:func:`bsi_sklearn.inference.mcmc.sampling_count`) times :data:`SAMPLING_TO_EXACT`, the exact
work units one unit of it is worth; never more than :data:`AUTO_MAX_WORK`, and never more
memory than :data:`AUTO_EXACT_BYTES`. Both are counts of the data and the parameters, never
timings, so the choice is the same on every machine (``docs/auto-budget.md``; the factor is
measured by ``scripts/calibrate_auto_budget.py``).
"""

from bsi_sklearn.inference.mcmc import sampling_count

__all__ = ["AUTO_EXACT_WORK", "AUTO_MAX_WORK", "AUTO_EXACT_BYTES", "SAMPLING_TO_EXACT",
           "auto_work_budget"]

#: Least work budget (exact.exact_posterior's max_work): about a second.
AUTO_EXACT_WORK = 1.5e8
#: Most work budget, however dear the sampling: an exact attempt that may fail must not cost
#: minutes (the calibration's dearest exact fit took 4.4e9; ``docs/auto-budget.md``).
AUTO_MAX_WORK = 1e10
#: Memory limit of an exact attempt under ``"auto"`` (``exact_posterior``'s ``max_bytes``):
#: past it the classifier samples instead.
AUTO_EXACT_BYTES = 2**30
#: Exact work units one unit of the sampler's count is worth.
SAMPLING_TO_EXACT = 24.0


def auto_work_budget(truth, y01, model, *, n_chains, n_samples, burn_in,
                     n_temperatures="auto"):
    """The exact engine's ``max_work`` under ``inference="auto"``.

    Parameters
    ----------
    truth : ndarray (n_demos, n_clauses)
        Clause truth (:func:`bsi_sklearn.model.clauses.clause_truth`).
    y01 : ndarray (n_demos,)
        Labels in {0, 1}.
    model : Model
    n_chains, n_samples, burn_in, n_temperatures
        The MCMC the classifier would fall back to.

    Returns
    -------
    max_work : float
    """
    count = sampling_count(truth, y01, model, n_chains=n_chains, n_samples=n_samples,
                           burn_in=burn_in, n_temperatures=n_temperatures)
    return min(max(AUTO_EXACT_WORK, SAMPLING_TO_EXACT * count), AUTO_MAX_WORK)
