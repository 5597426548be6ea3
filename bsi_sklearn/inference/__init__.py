"""Inference: the posterior over specifications from clause truth and a model.

One entry, :func:`bsi_sklearn.inference.policy.infer`, which chooses the engine and returns
one :class:`~bsi_sklearn.inference.policy.InferenceResult` that
:meth:`bsi_sklearn.Posterior.from_result` turns into a posterior; two engines behind it:

- :mod:`bsi_sklearn.inference.exact`: the exact posterior, by a bounded enumeration of the
  prior's support over groups of interchangeable parts (the reference everything else is
  tested against);
- :mod:`bsi_sklearn.inference.mcmc`: tempered Gibbs chains in numba, for what exact cannot
  finish (:func:`~bsi_sklearn.inference.mcmc.sample_posterior`);
- :mod:`bsi_sklearn.inference.auto_budget`: how much exact work ``inference="auto"`` allows
  before it samples (at least about a second; as much as the sampling would cost);
- :mod:`bsi_sklearn.inference.diagnostics`: split-R-hat, the mass each chain missed, total
  variation, the thresholds of the convergence warnings.

The underscore modules (kernels, grouping, the ungrouped reference, the chain kernel and its
Gibbs moves, the local search) are private to this package.
"""
