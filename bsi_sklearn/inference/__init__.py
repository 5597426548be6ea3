"""Inference: the posterior over specifications from clause truth and a model.

Two engines, each returning a result bundle that :class:`bsi_sklearn.BSIClassifier` turns into a
:class:`bsi_sklearn.Posterior`:

- :mod:`bsi_sklearn.inference.exact`: the exact posterior, by a bounded enumeration of the
  prior's support over groups of interchangeable parts (the reference everything else is
  tested against);
- :mod:`bsi_sklearn.inference.mcmc`: Gibbs chains in numba, for what exact cannot finish;
- :mod:`bsi_sklearn.inference.diagnostics`: split-R-hat, the mass each chain missed, total
  variation.

The underscore modules (kernels, grouping, the ungrouped reference, the Gibbs moves) are private
to this package.
"""
