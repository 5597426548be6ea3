"""The model bundle: every parameter of the BSI model that a kernel reads, built once per fit.

:class:`Model` is a NamedTuple of scalars and small arrays, which numba accepts as one
argument: the clause, exact and MCMC kernels take it instead of a dozen positional parameters.
Which prior and likelihood it holds travels as an integer code; only
:mod:`bsi_sklearn.model.priors` and :mod:`bsi_sklearn.model.likelihood` give those codes
meaning.
"""

from typing import NamedTuple

import numpy as np

from bsi_sklearn.model.flip_rate import log_flip_marginals
from bsi_sklearn.model.likelihood import likelihood_code, resolve_flip_prior, resolve_log_epsilon
from bsi_sklearn.model.priors import LEARNED, prior_code, prior_tables

__all__ = ["Model", "make_model", "describe_globals"]


class Model(NamedTuple):
    """Parameters of the prior and the likelihood for one template size.

    Built by :func:`make_model`; the field order is part of the kernels' typing, so add
    fields at the end.
    """

    n_g: int                  # number of global candidates |T|
    n: int                    # number of subtasks |Omega|
    prior: int                # prior_code(prior name)
    forest: bool              # order structures are forests (Prior 3), not sets of chains
    p_global: float
    p_eventual: float
    p_part: float
    n_new: float
    log_eps: float
    likelihood: int           # likelihood_code(likelihood name)
    lp_chains: np.ndarray     # log prior of a chain structure by its number of chains
    forest_g: np.ndarray      # Prior 3: log prior = forest_const + sum_v forest_g[size of v]
    forest_const: float
    flip_a: float             # Beta(a, b) prior of the flip rate (likelihood code 2), else 0
    flip_b: float
    pat_in: np.ndarray        # log p, log(1 - p) of each pattern clause: the last
    pat_out: np.ndarray       # len(pat_in) global slots (DESIGN §12); empty for the paper's
    flips: np.ndarray         # codes 2 and 4: the labels' log marginal likelihood by number of
    #                           misclassified demonstrations, 0 .. n_demos; else empty


def make_model(*, prior, likelihood, n_globals, n_subtasks, p_global=0.8, p_eventual=0.8,
               p_part=0.3, n_new=5.0, epsilon=None, flip_prior=None, p_patterns=(),
               n_demos=None):
    """Build the model bundle of one fit.

    Parameters
    ----------
    prior : {"linear_chain", "sets_of_chains", "forest"}
    likelihood : {"cb", "ci", "calibrated"}
    n_globals, n_subtasks : int
        Numbers of global slots (the ``G`` candidates, then the pattern clauses) and subtasks.
    p_global, p_eventual : float or "learned"
        Prior inclusion probabilities (see :class:`~bsi_sklearn.BSIClassifier`); ``"learned"``
        is held as :data:`~bsi_sklearn.model.priors.LEARNED`.
    p_part : float or "learned"
        Prior 2's probability of a new chain (see :class:`~bsi_sklearn.BSIClassifier`);
        ``"learned"`` is held as :data:`~bsi_sklearn.model.priors.LEARNED`.
    n_new : float
        Prior 3's weight of a new tree.
    epsilon : float or None
        Likelihood of a misclassified demonstration; ``None`` for the paper's default.
    flip_prior : tuple of float or None
        ``(a, b)``: with ``"ci"`` or ``"calibrated"``, the flip rate integrated over a
        Beta(a, b) prior restricted to (0, 1/2)
        (:func:`bsi_sklearn.model.likelihood.resolve_flip_prior` says where it applies;
        :mod:`bsi_sklearn.model.flip_rate`).
    p_patterns : array-like of float, default=()
        Inclusion probability of each pattern clause (DESIGN §12), the last
        ``len(p_patterns)`` of the ``n_globals`` global slots; the ``G`` clauses before them
        have ``p_global``. Empty: the paper's template.
    n_demos : int, default=None
        Number of training demonstrations: needed with ``flip_prior``, whose marginal
        likelihood is tabled by the number of them a formula misclassifies.

    Returns
    -------
    Model

    Examples
    --------
    >>> m = make_model(prior="forest", likelihood="cb", n_globals=2, n_subtasks=3)
    >>> m.n_g, m.n, m.forest, round(m.log_eps, 3)
    (2, 3, True, -22.181)
    """
    n_g, n = int(n_globals), int(n_subtasks)
    pat_p = np.asarray(p_patterns, dtype=float).reshape(-1)
    if len(pat_p) > n_g or np.any(~((pat_p > 0) & (pat_p < 1))):
        raise ValueError(f"p_patterns must hold at most n_globals = {n_g} probabilities in "
                         f"(0, 1), got {pat_p.tolist()}")
    flip_a, flip_b = resolve_flip_prior(likelihood, flip_prior, epsilon)
    if flip_a > 0 and n_demos is None:
        raise ValueError("make_model needs n_demos with a flip_prior: the labels' marginal "
                         "likelihood is tabled by the number of misclassified demonstrations")
    flips = (log_flip_marginals(int(n_demos), flip_a, flip_b) if flip_a > 0
             else np.zeros(0))
    forest, lp_chains, forest_g, forest_const = prior_tables(prior, n, _inclusion(p_part),
                                                             float(n_new))
    return Model(
        n_g=n_g, n=n, prior=prior_code(prior), forest=bool(forest),
        p_global=_inclusion(p_global), p_eventual=_inclusion(p_eventual),
        p_part=_inclusion(p_part), n_new=float(n_new),
        log_eps=float(resolve_log_epsilon(epsilon, n_g, n)),
        likelihood=likelihood_code(likelihood, flip_prior), lp_chains=lp_chains,
        forest_g=forest_g, forest_const=float(forest_const), flip_a=flip_a, flip_b=flip_b,
        pat_in=np.log(pat_p), pat_out=np.log1p(-pat_p), flips=flips,
    )


def _inclusion(p):
    # A subset's inclusion probability as the kernels read it: LEARNED where it is learned.
    return LEARNED if isinstance(p, str) and p == "learned" else float(p)


def describe_globals(model):
    """The global slots of a model for a message (``"3 global candidates"``).

    With pattern clauses: ``"870 global slots (2 global candidates, 868 pattern clauses)"``.
    """
    n_pat = model.pat_in.shape[0]
    if not n_pat:
        return f"{model.n_g} global candidates"
    return (f"{model.n_g} global slots ({model.n_g - n_pat} global candidates, {n_pat} "
            "pattern clauses)")
