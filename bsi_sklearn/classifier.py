"""`BSIClassifier`: Bayesian Specification Inference as a scikit-learn classifier."""

import dataclasses
import math
from numbers import Integral, Real

import numpy as np
from sklearn.base import BaseEstimator, ClassifierMixin
from sklearn.utils.validation import check_is_fitted

from bsi_sklearn._compile_progress import compile_progress
from bsi_sklearn.data.inferred_roles import infer_roles
from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_consistent_traces, check_labels, check_traces
from bsi_sklearn.inference.policy import InferencePolicy, infer
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_truth
from bsi_sklearn.model.likelihood import LIKELIHOODS, is_flip_prior
from bsi_sklearn.model.pattern_candidates import (
    check_p_patterns,
    check_templates,
    pattern_candidates,
    pattern_probabilities,
)
from bsi_sklearn.model.priors import PRIORS
from bsi_sklearn.param_validation import (
    NONZERO_INTEGER,
    Interval,
    Satisfies,
    StrOptions,
    validate_params,
)
from bsi_sklearn.posterior import Posterior
from bsi_sklearn.predictive import label_noise, misclassified, predictive_log_proba
from bsi_sklearn.specification.templates import TEMPLATE_SETS

__all__ = ["BSIClassifier"]

_INFERENCE = ("auto", "exact", "mcmc")
_VOTES = ("predictive", "satisfaction")


class BSIClassifier(ClassifierMixin, BaseEstimator):
    """Bayesian Specification Inference classifier (Shah et al., 2019).

    Infers a posterior over LTL formulas
    ``G(tau) & (pi_w -> F omega_w) & (pi_a -> (!omega_b U omega_a))`` from demonstrations (boolean
    proposition traces) labelled acceptable (1) or not (0). ``predict_proba(X)[:, 1]`` is the
    posterior predictive probability that a demonstration is labelled acceptable, over the
    formulas and the label noise; ``vote="satisfaction"`` gives the paper's vote instead.

    Parameters
    ----------
    prior : {"linear_chain", "sets_of_chains", "forest"}, default="sets_of_chains"
        Prior over the order structure: Prior 1 (one permutation of all subtasks), Prior 2 (sets
        of disjoint chains) or Prior 3 (forest of subtasks).
    likelihood : {"cb", "ci", "calibrated"}, default="calibrated"
        The size principle calibrated by the data (a clause earns only through the
        demonstrations it moves across the boundary), the paper's complexity-based likelihood
        (``"cb"``: the size principle, every conjunct earning on every satisfied acceptable
        demonstration), or the complexity-independent one (``docs/likelihoods.md``;
        ``benchmarks/RESULTS_default_candidates.md`` for why ``"calibrated"`` is the default).
    global_candidates : list of str or int, default=None
        Propositions that may be required to hold always (the set T). ``None``: set by
        ``roles``, read from the training demonstrations by default (``roles="infer"``).
    subtasks : list of str or int, default=None
        Subtask-completion propositions (the set Omega). ``None``: set by ``roles``, read
        from the training demonstrations by default (``roles="infer"``).
    conditions : dict, default=None
        Subtask -> condition proposition ``pi_w`` (read at t = 0). Subtasks without an entry
        have ``pi_w = true``; ``{}``: no conditions. ``None``: set by ``roles``, read from the
        training demonstrations by default (``roles="infer"``).
    roles : {"infer", "all"}, default="infer"
        What the roles left at ``None`` become. ``"infer"``: read from the training
        demonstrations (propositions whose clauses they can test, each subtask's condition
        from the initial values that separate the acceptable demonstrations completing it
        from those skipping it; :func:`bsi_sklearn.data.inferred_roles.infer_roles`). ``"all"``:
        every proposition a global candidate and a subtask, no conditions (the paper's
        setting without an expert's roles: vacuous clauses and chance orders then enter the
        MAP). Roles given explicitly are used as given; ``roles_`` says what was used; see
        ``docs/roles.md``.
    templates : "paper", "unary", "declare", "all" or list of str, default="paper"
        Pattern clauses the specification may hold besides the paper's template (DESIGN
        §12): names of the catalogue (``"Response"``, ``"AtMostOnce"``, ...;
        :data:`bsi_sklearn.specification.templates.TEMPLATES`) or LTLf formulas with
        placeholders (``"G(x -> F(y))"``). Each template is instantiated over the
        propositions that hold somewhere in the training demonstrations, instances every
        training demonstration satisfies set apart as vacuous; each instance is then an
        independent inclusion, like a ``G`` clause. ``"paper"``: the paper's template alone,
        exactly; ``"unary"``, ``"declare"``, ``"all"``: the catalogue's templates of one slot,
        its Declare templates, all of it
        (:data:`bsi_sklearn.specification.templates.TEMPLATE_SETS`).
    p_global : float or "learned", default=0.8
        Prior inclusion probability of each ``G`` clause. ``"learned"``: unknown, uniform on
        (0, 1) and integrated out (Scott and Berger's multiplicity correction, 2010): every
        number of clauses is equally probable a priori, so among many candidates each one
        more costs about ``log(candidates / clauses)`` nats, and a clause the data do not ask
        for is left out (``docs/likelihoods.md``).
    p_eventual : float or "learned", default=0.8
        Prior inclusion probability of each eventual clause; ``"learned"`` as for
        ``p_global``.
    p_patterns : float or dict, default=None
        Prior inclusion probability of each pattern clause: one for all, or a dict from
        template family (``"relation"``) or name (``"Response"``) to one. ``None`` (and the
        families and names a dict leaves out): the family's default,
        :data:`bsi_sklearn.model.pattern_candidates.FAMILY_P` (0.2 for existence and
        absence, 0.1 for relations and choices, 0.05 for orderings, negations and scopes).
    p_part : float or "learned", default=0.3
        Probability of starting a new chain after each subtask (Prior 2). ``"learned"``:
        unknown, uniform on (0, 1) and integrated out, so that every number of chains is
        equally probable a priori; where few subtasks are ordered, the first order costs
        ``log(n (n - 1))`` nats among ``n`` subtasks (0.3: ``log(n / 2.33)``), so that an order
        the data do not ask for is left out, as ``"learned"`` does for ``p_eventual``
        (``docs/likelihoods.md``).
    n_new : float, default=5.0
        Weight of a new tree (Prior 3).
    epsilon : float, default=None
        Likelihood of a misclassified demonstration, in (0, 1). ``None`` uses the paper's
        ``log eps = -4 log(2) (|T| + |Omega| + |Omega|(|Omega|-1)/2)``.
    flip_prior : (float, float), default=None
        ``(a, b)``: with ``"ci"`` or ``"calibrated"``, labels are flipped at a rate with a
        Beta(a, b) prior restricted to (0, 1/2) (mostly right labels: no formula explains
        them as mostly flipped), integrated out (``docs/likelihoods.md``; e.g. ``(1, 9)``).
        With ``"calibrated"`` a flipped label then costs about ``log(n / v)`` nats (``v`` of
        ``n`` labels misclassified), not ``epsilon``'s penalty.
    vote : {"predictive", "satisfaction"}, default="predictive"
        What :meth:`predict_proba` returns. ``"predictive"``: P(label = acceptable | X, data),
        over the formulas *and* the label noise (a formula's violators are labelled acceptable
        with its flip rate: ``epsilon``, or with ``flip_prior`` the flip rate's posterior mean
        given the formula; ``docs/likelihoods.md``). ``"satisfaction"``: the paper's vote, the
        posterior mass of the formulas a demonstration satisfies. Read at prediction time.
    label_noise : {"learned", "likelihood"}, default="learned"
        The flip rate of each formula in the predictive (``vote="predictive"``).
        ``"learned"``: its posterior mean given the training demonstrations the formula
        misclassifies, ``(a + v) / (a + b + n)`` under the uniform prior ``(a, b) = (1, 1)``
        or, with a ``flip_prior``, the mean of its posterior restricted to (0, 1/2): the
        specification is inferred by the likelihood, the noise from the labels given the
        specification (a cut model, ``docs/likelihoods.md``).
        ``"likelihood"``: the likelihood's ``epsilon`` (CB's default ``epsilon`` is a penalty of
        about ``e^-55``, not a rate, so its probabilities are nearly 0 or 1). Read at
        prediction time.
    inference : {"auto", "exact", "mcmc"}, default="auto"
        ``"auto"`` enumerates the posterior exactly when the enumeration needs at most about a
        second of work on a 2020s CPU core or, if more, what the MCMC it would fall back to
        costs (chains x sweeps x rungs x moves x demonstrations; ``docs/auto-budget.md``),
        however large the support, within caps (1e10 work units, 1 GiB of tables), and
        samples with MCMC otherwise; work is counted, not timed: the same choice on every
        machine and for every ``n_jobs`` (a peaked posterior over 1e19 hypotheses can be
        cheap, a nearly flat one over 1e8 expensive).
        ``"exact"`` has a memory limit only (4 GiB of tables, counted before allocation):
        beyond it, a ``ValueError`` names the size and the cure. ``inference_`` says which.
    n_samples : int or "auto", default="auto"
        MCMC sweeps recorded per chain, after ``burn_in`` (a sweep redraws every coordinate);
        ``"auto"``: at most 10,000, in rounds that stop once the chains agree (see Notes).
    burn_in : int, default=100
        MCMC sweeps discarded at the start of every chain.
    n_chains : int, default=4
        Independent MCMC chains, each a ladder of replicas started from the deterministic
        optimum (see Notes).
    n_temperatures : "auto" or int, default="auto"
        Replicas per chain for parallel tempering: rung ``k`` samples prior x likelihood^beta_k
        and adjacent rungs swap; only beta = 1 is recorded. ``"auto"``: beta halves from rung
        to rung down to ``1 / L``, ``L = max(|log eps|, n_pos log 2)`` (the likelihood's step
        for one demonstration or, CB, one conjunct; ``n_pos`` acceptable demonstrations), so
        ``1 + ceil(log2 L)`` rungs (8 for 72 demonstrations of the paper's LFE template),
        and the burn-in (at least 20 sweeps) is a pilot on that ladder after which the chains
        keep its two ends and only as many rungs as the measured swap rejections call for
        (about ``2 Lambda``, ``Lambda`` their sum; 4 to 8 on the LFE template; see Notes);
        the first 500 recorded sweeps then run on one rung and are kept if the chains already
        agree after them (a fixed ``n_samples`` above 500 records the rest on one rung too).
        An integer sets the number of rungs between 1 and
        ``1 / L``, not adapted; 1 turns tempering off. Time grows linearly with the rungs that
        move.
    max_exact_hypotheses : int or None, default=None
        Largest support enumerated exactly; ``None``: no cap (``"auto"`` decides by the work
        alone). Exact inference sums interchangeable parts of the hypotheses and skips, with a
        bound, those that cannot add 1e-17 of the posterior, so its time depends on the data,
        not on the support's size: the paper's dinner table (2.0e8 hypotheses under Prior 2,
        2.4e9 under Prior 3) takes milliseconds, and the LFE missions with every proposition in
        every role (3.5e15 under Prior 2) tens of milliseconds. With a cap, ``"auto"`` samples
        larger supports and ``"exact"`` refuses them.
    tol : float, default=1e-9
        Posterior mass exact inference may drop (its least probable hypotheses); the mass
        actually dropped is ``posterior_.dropped_mass``.
    binarize : float, default=None
        When set, trace values ``> binarize`` are true; otherwise traces must be 0/1 or bool.
    pos_label : int, str or bool, default=None
        The acceptable label, needed when labels are not 0/1 or booleans.
    n_jobs : int, default=None
        Chains run in parallel threads of the fitting process (the numba kernels release the
        GIL). An outer joblib backend (e.g. dask, for cross-validation) distributes whole fits;
        the chains of one fit stay local.
    random_state : int, RandomState instance or None, default=None
        Seeds of the chains are drawn from it; results do not depend on ``n_jobs``.
    verbose : int, default=0
        When > 0: a progress bar over chains, and one over the numba kernels compiled on the
        first fit in a fresh environment (later processes load them from numba's cache).

    Attributes
    ----------
    classes_ : ndarray of shape (2,)
        ``[unacceptable, acceptable]`` labels; ``[0, 1]`` for 0/1 labels and positive-only fits.
    n_features_in_ : int
        Number of propositions.
    roles_ : dict
        The roles used, as parameters (``BSIClassifier(**clf.roles_)`` fits with them):
        ``global_candidates``, ``subtasks`` and ``conditions`` (subtask -> condition), by
        proposition name for DataFrames and by column index otherwise.
    pattern_candidates_ : list of (str, list)
        The pattern clauses the fit considered (``templates``): template name and the
        propositions filling its slots. Empty with ``templates="paper"``.
    feature_names_in_ : ndarray of str
        Proposition names, when the demonstrations were DataFrames with string columns.
    posterior_ : Posterior
        The inferred posterior over unique specifications.
    map_specification_ : Specification
        The most probable specification (``posterior_.map_specification``; of a posterior
        reported by its samples, the most probable found, not the most often sampled);
        ``.readable(vacuous_clauses_)`` shows it to a person.
    vacuous_clauses_ : frozenset of clause keys
        Candidate clauses every training demonstration satisfies, acceptable or not: untested
        (see :meth:`Posterior.mark_vacuous <bsi_sklearn.Posterior.mark_vacuous>`).
    n_unique_specifications_ : int
        Number of specifications in ``posterior_``.
    inference_ : str
        ``"exact"`` or ``"mcmc"``: what ``fit`` did.
    n_hypotheses_ : int
        Size of the prior's support.
    log_epsilon_ : float
        ``log(epsilon)`` used by the likelihood.
    flip_rate_, flip_rate_interval_ : float, (float, float)
        With ``flip_prior``, the flip rate's posterior mean and central 95% interval
        (``docs/likelihoods.md``); ``None`` without.
    mcmc_diagnostics_ : dict or None
        For MCMC (``None`` after exact inference):

        - ``rhat``: split-R-hat of the chains' log posteriors (``inf`` when chains sit on
          different values, ``nan`` with fewer than 4 samples);
        - ``missed_mass_per_chain``, ``max_missed_mass``: the mass each chain never reached,
          as ``n_samples="auto"``'s stopping rule counts it: among the states found, those
          its visited states do not lead to through the weighed neighbours (one Gibbs block,
          or one exchange of two subtasks between ties of the best); past the closure's
          budget, or with a fixed ``n_samples``, among the states the chains visited, those
          it neither visited nor weighed one block from a state it visited (the total
          variation between that chain's own reweighted posterior and theirs); ``nan`` for
          a posterior too diffuse to list (``typical_gap``), where exact weights say
          nothing;
        - ``optimum_log_posterior``: the log posterior (unnormalised) of a deterministic
          optimum (a beam search over one-block changes), where every chain starts;
          ``best_visited_log_posterior``: the best state the chains recorded;
          ``optimum_gap``: the first less the second; ``typical_gap``: the visited
          states' mean log posterior, reweighted exactly, less the chains';
          ``unseen_mass``: the share of the samples whose state was sampled once (the
          Good-Turing estimate of the mass in states never visited). Above log 20 and 0.05
          the posterior is too diffuse to list and ``sampled`` is ``True``, as it is where
          as much is unseen and the states found fail the missed mass's check while the
          chains agree, or where their posterior's inclusion of a clause lies beyond the
          samples' noise from the samples', by more than 0.01 (``listing_gap``: the
          largest such gap, 0.0 where none is or where little is unseen): the
          probabilities are the sample frequencies, and
          ``inclusion_rhat``, the largest split-R-hat of a clause's inclusion across the
          chains, says whether they agree (else ``None``);
        - ``betas``: the tempering ladder the chains recorded on; ``ladder``: with
          ``n_temperatures="auto"``, the pilot's ``default_betas``, ``pilot_rejection`` (mean
          rejection probability of each pair's swaps over the pilot's second half, the
          chains pooled), ``barrier`` (their sum) and ``restarted`` (the chains whose beta =
          1 replica ended the pilot so far below the best chain's that their samples would
          provably hold no mass: they go on from its state), ``adapted_betas`` (the ladder
          after the pilot) and ``untempered`` (whether the samples are the untempered first
          round's), else ``None``; ``swap_rate``
          (chains x rung pairs): accepted swaps after the pilot; ``burn_in_per_chain``:
          sweeps each chain discarded, the pilot's included;
        - ``acceptance_rate`` (and ``_per_chain``): fraction of the beta = 1 replica's block
          updates that changed its state; ``n_updates``: block updates of all replicas;
        - ``n_visited``: states the chains recorded; ``n_added``: states of ``posterior_``
          they did not (the optimum and the completed neighbourhood);
          ``sample_frequencies``: each specification's frequency among the samples (0 for
          added ones); ``log_posterior_traces`` (chains x samples); ``seeds``, ``n_chains``,
          ``n_samples`` (sweeps each chain recorded), ``burn_in``; ``stopping``: the rounds
          of ``n_samples="auto"`` (each one's ``max_missed_mass``, ``rhat``, ``late_mass``,
          and past the closure's budget ``max_inclusion_gap``; a round of a posterior
          reported by its samples has ``rhat`` and ``inclusion_rhat``); ``restarted``:
          whether chains whose samples lay where the posterior provably has no mass (far
          below the best state found: ``inference/_negligible.py``) went on from that state,
          ``negligible_burn_in`` the samples every chain burned for it, ``lost_chains`` the
          chains left out (absent from the per-chain entries above).

    See Also
    --------
    bsi_sklearn.Specification : the formulas of the posterior.

    Notes
    -----
    The MCMC sampler discovers the posterior's support; the probabilities it reports are the
    exact posterior restricted to that support, renormalised, which is far closer to the exact
    posterior than sample frequencies (kept in ``mcmc_diagnostics_``), except where the
    posterior is too diffuse for a support to hold it (``typical_gap`` above log 20, or the
    support fails its own check, ``max_missed_mass`` above 5 % while the chains agree on every
    clause's inclusion, or it does not report what the chains sample, ``listing_gap`` above
    0.01; each only where ``unseen_mass`` is above 5 %): there they are the
    sample frequencies
    (``mcmc_diagnostics_["sampled"]``), listed most often sampled first, and the MAP is still
    the most probable specification found (``posterior_.map_index``; the deterministic
    optimum, which may hold too little of the mass to be sampled at all). Every chain
    runs a ladder of tempered replicas (``n_temperatures``) from the deterministic optimum (a
    beam search's best basin, which single-coordinate moves often miss on large problems) for
    ``burn_in`` sweeps, and while it is 20 times less probable than the optimum for up to as
    many more. The burn-in runs on the default ladder and measures how often each pair of
    adjacent rungs refuses a swap; the chains then go on with the same coldest and hottest
    rungs and the fewest rungs in between that keep about half the swaps accepted, placed at
    equal steps of the summed rejections (the schedule of non-reversible parallel tempering,
    Syed et al. 2022), one ladder for every chain. Rungs whose replicas sit in the same state
    cost almost nothing, so the time saved is less than the rungs shed. Tempering is there to
    find modes, and the pilot has searched: the first round (500 sweeps) runs untempered
    from the pilot's beta = 1 replicas and is kept if the stopping rule below holds after it
    (a fixed ``n_samples`` records the rest untempered too, and is weighed as the rounds
    are); otherwise its sweeps are burn-in and the chains record on the adapted ladder (on a
    100-activity event log the plateau of weakly determined clauses is sampled alike on every
    rung, and the swaps only slowed the chains' agreement: 364 s against 38 s).
    ``n_samples="auto"``
    records 500, 1,000, 2,000, ... up to 10,000 sweeps, until the chains agree and stop finding
    mass, or, where the support is too large to list (a diffuse posterior), agree on every
    clause's posterior inclusion within 0.01, or, for a posterior reported by its samples, on
    every clause's inclusion (its split-R-hat across them at most 1.01;
    :mod:`bsi_sklearn.inference.stopping`). The support is what the chains recorded, the
    optimum, and the one-block neighbours of the states holding 99% of the mass (in a flat
    posterior, states too improbable to be visited add up).

    A ``ConvergenceWarning`` is raised when the optimum is more than 20 times as probable as
    every state the chains recorded (they left it and agree on a worse mode), when some chain
    never reached more than 5% of the mass the chains found (``max_missed_mass``: they
    disagree), and when the split-R-hat exceeds 1.05 (with one chain, the halves of its
    trace are compared, and no chain can disagree); on a posterior reported by its samples,
    only the last (the first two weigh states by their exact posterior). With
    ``roles="all"`` (every proposition a global candidate and a subtask) and a support that
    ``"auto"`` could not enumerate, a ``UserWarning`` suggests ``global_candidates``,
    ``subtasks`` and ``conditions``.

    References
    ----------
    A. Shah, P. Kamath, S. Li, P. Craven, K. Lande, J. A. Shah. Supervised Bayesian
    Specification Inference from Demonstrations. 2019.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> # propositions: safe, a_done, b_done; every demonstration does a before b, safely
    >>> X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
    ...      np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    >>> clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], random_state=0).fit(X)
    >>> print(clf.map_specification_.to_ltl())
    G(0) & F(1) & F(2) & (!2 U 1)
    >>> clf.predict([np.array([[1, 0, 1], [1, 1, 1]])])
    array([0])
    """

    def __init__(self, *, prior="sets_of_chains", likelihood="calibrated", global_candidates=None,
                 subtasks=None, conditions=None, roles="infer", templates="paper",
                 p_global=0.8, p_eventual=0.8, p_patterns=None, p_part=0.3, n_new=5.0,
                 epsilon=None, flip_prior=None, vote="predictive",
                 label_noise="learned", inference="auto", n_samples="auto", burn_in=100,
                 n_chains=4, n_temperatures="auto", max_exact_hypotheses=None, tol=1e-9,
                 binarize=None, pos_label=None, n_jobs=None, random_state=None, verbose=0):
        self.prior = prior
        self.likelihood = likelihood
        self.global_candidates = global_candidates
        self.subtasks = subtasks
        self.conditions = conditions
        self.roles = roles
        self.templates = templates
        self.p_global = p_global
        self.p_eventual = p_eventual
        self.p_patterns = p_patterns
        self.p_part = p_part
        self.n_new = n_new
        self.epsilon = epsilon
        self.flip_prior = flip_prior
        self.vote = vote
        self.label_noise = label_noise
        self.inference = inference
        self.n_samples = n_samples
        self.burn_in = burn_in
        self.n_chains = n_chains
        self.n_temperatures = n_temperatures
        self.max_exact_hypotheses = max_exact_hypotheses
        self.tol = tol
        self.binarize = binarize
        self.pos_label = pos_label
        self.n_jobs = n_jobs
        self.random_state = random_state
        self.verbose = verbose

    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.input_tags.three_d_array = True
        tags.input_tags.two_d_array = True
        tags.classifier_tags.multi_class = False
        # Generic numeric benchmarks (blobs) are not temporal specifications.
        tags.classifier_tags.poor_score = True
        tags.target_tags.required = False
        tags.non_deterministic = False
        return tags

    # ------------------------------------------------------------------ validation
    # The proposition roles and pos_label are checked against the data, in fit.
    _parameter_constraints = {
        "prior": [StrOptions(PRIORS)],
        "likelihood": [StrOptions(LIKELIHOODS)],
        "global_candidates": "no_validation",
        "subtasks": "no_validation",
        "conditions": "no_validation",
        "roles": [StrOptions({"all", "infer"})],
        "templates": [StrOptions({"paper", *TEMPLATE_SETS}), list, tuple],
        "p_global": [Interval(Real, 0.0, 1.0, closed="both"), StrOptions({"learned"})],
        "p_eventual": [Interval(Real, 0.0, 1.0, closed="both"), StrOptions({"learned"})],
        "p_patterns": [None, Satisfies(check_p_patterns, "a probability in (0, 1) or a mapping "
                                                         "from template family or name to one")],
        "p_part": [Interval(Real, 0.0, 1.0, closed="both"), StrOptions({"learned"})],
        "n_new": [Interval(Real, 0.0, math.inf, closed="neither")],
        "epsilon": [Interval(Real, 0.0, 1.0, closed="neither"), None],
        "flip_prior": [None, Satisfies(is_flip_prior, "a pair (a, b) of positive numbers")],
        "vote": [StrOptions(_VOTES)],
        "label_noise": [StrOptions({"learned", "likelihood"})],
        "inference": [StrOptions(_INFERENCE)],
        "n_samples": [StrOptions({"auto"}), Interval(Integral, 1, None, closed="left")],
        "burn_in": [Interval(Integral, 0, None, closed="left")],
        "n_chains": [Interval(Integral, 1, None, closed="left")],
        "n_temperatures": [StrOptions({"auto"}), Interval(Integral, 1, None, closed="left")],
        "max_exact_hypotheses": [Interval(Integral, 0, None, closed="left"), None],
        "tol": [Interval(Real, 0.0, 1.0, closed="left")],
        "binarize": [None, Interval(Real, None, None, closed="neither")],
        "pos_label": "no_validation",
        "n_jobs": [None, NONZERO_INTEGER],
        "random_state": ["random_state"],
        "verbose": [Interval(Integral, 0, None, closed="left")],
    }

    def _validate_params(self):
        """Check the parameters against ``_parameter_constraints`` (raises ValueError)."""
        validate_params(self.get_params(deep=False), self._parameter_constraints,
                        type(self).__name__)

    # ------------------------------------------------------------------ fit
    def fit(self, X, y=None):
        """Infer the posterior over specifications from demonstrations.

        Parameters
        ----------
        X : list of array-like or DataFrame, or ndarray
            Demonstrations (see :func:`bsi_sklearn.data.traces.check_traces`): a list of
            ``(T_i, n_props)`` boolean traces or DataFrames (``[df]`` for one), a 3-D array
            ``(n_demos, T, n_props)``, a long-format DataFrame with a ``demo_id`` column, or a
            2-D array whose rows are traces of length one. A single DataFrame without
            ``demo_id`` and a list of 1-D arrays are rejected with a ``ValueError`` that says
            what to pass instead.
        y : array-like of shape (n_demos,), default=None
            1 (acceptable) or 0 (unacceptable). ``None`` or all ones: learn from positives only.

        Returns
        -------
        self : BSIClassifier
        """
        # A fresh environment compiles the numba kernels on this first fit (seconds): a bar
        # says so when verbose > 0.
        with compile_progress(self.verbose):
            return self._fit(X, y)

    def _fit(self, X, y):
        self._validate_params()
        traces = check_traces(X, binarize=self.binarize, estimator_name=type(self).__name__)
        y01, classes = check_labels(y, traces.n_demos, self.pos_label)
        given = (self.global_candidates, self.subtasks, self.conditions)
        roles = (infer_roles(traces, y01, *given) if self.roles == "infer" else
                 resolve_roles(*given, traces.n_props, traces.feature_names))
        names = check_templates(self.templates)
        p_pat, block = [], None
        if names:  # pattern clauses: global slots after the G candidates (DESIGN §12)
            candidates, block, _ = pattern_candidates(traces, names)
            roles = dataclasses.replace(roles, patterns=candidates)
            probs = pattern_probabilities(names, self.p_patterns)
            p_pat = [probs[name] for name, _ in candidates]
        n_g, n = roles.n_global_slots, roles.n_subtasks
        truth = clause_truth(traces, roles, block)
        model = make_model(prior=self.prior, likelihood=self.likelihood, n_globals=n_g,
                           n_subtasks=n, p_global=self.p_global, p_eventual=self.p_eventual,
                           p_part=self.p_part, n_new=self.n_new, epsilon=self.epsilon,
                           flip_prior=self.flip_prior, p_patterns=p_pat, n_demos=len(y01))
        policy = InferencePolicy(
            inference=self.inference, prior=self.prior,
            max_exact_hypotheses=self.max_exact_hypotheses, tol=self.tol,
            n_chains=self.n_chains, n_samples=self.n_samples, burn_in=self.burn_in,
            n_temperatures=self.n_temperatures, n_jobs=self.n_jobs, verbose=self.verbose,
            random_state=self.random_state,
            warn_all_roles=self.roles == "all" and given == (None,) * 3)
        result = infer(truth, y01, model, policy)
        self.posterior_ = Posterior.from_result(result, roles)
        self.mcmc_diagnostics_ = result.diagnostics
        self.flip_rate_, self.flip_rate_interval_ = result.flip_rate(len(y01), self.flip_prior)
        violations = (misclassified(self.posterior_._masks, truth, y01)
                      if result.violations is None
                      else np.asarray(result.violations, dtype=float))
        self._noise_data = (violations, len(y01), model.log_eps, self.flip_prior)
        self.classes_ = classes
        self.n_features_in_ = traces.n_props
        self.roles_ = roles.to_params()
        self.pattern_candidates_ = [(name, list(props)) for name, props in roles.pattern_keys()]
        if traces.feature_names is not None:
            self.feature_names_in_ = traces.feature_names
        elif hasattr(self, "feature_names_in_"):
            del self.feature_names_in_
        self.inference_ = result.engine
        self.n_hypotheses_ = result.n_hypotheses
        self.log_epsilon_ = model.log_eps
        self.map_specification_ = self.posterior_.map_specification
        self.vacuous_clauses_ = self.posterior_.mark_vacuous(traces, y01, truth=truth)
        self.n_unique_specifications_ = len(self.posterior_)
        return self

    # ------------------------------------------------------------------ prediction
    def _validated(self, X):
        check_is_fitted(self)
        traces = check_traces(X, binarize=self.binarize, estimator_name=type(self).__name__)
        check_consistent_traces(traces, self.n_features_in_,
                                getattr(self, "feature_names_in_", None), type(self).__name__)
        return traces

    def _by_satisfaction(self):
        # vote is read at prediction time (set_params needs no refit): checked here too.
        names = ("vote", "label_noise")
        validate_params({k: getattr(self, k) for k in names},
                        {k: self._parameter_constraints[k] for k in names}, type(self).__name__)
        return self.vote == "satisfaction"

    def _noise(self):
        """The :class:`LabelNoise` of the fitted posterior under ``label_noise``."""
        violations, n_demos, log_eps, flip_prior = self._noise_data
        return label_noise(violations, n_demos, log_eps, flip_prior, self.label_noise)

    def predict_proba(self, X):
        """Probability that each demonstration is acceptable.

        ``vote="predictive"``: P(label = acceptable | X, data), the posterior over formulas and
        label noise (``docs/likelihoods.md``, "The posterior predictive"); exact when the
        posterior is. ``vote="satisfaction"``: the posterior mass of the formulas X satisfies.

        Parameters
        ----------
        X : demonstrations, in any format accepted by :meth:`fit`.

        Returns
        -------
        proba : ndarray of shape (n_demos, 2)
            Columns follow ``classes_``; each row sums to 1.

        Examples
        --------
        >>> import numpy as np
        >>> from bsi_sklearn import BSIClassifier
        >>> X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),   # safe; a, then b: acceptable
        ...      np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]   # b before a: unacceptable
        >>> clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], likelihood="ci",
        ...                     flip_prior=(1, 9), random_state=0).fit(X, [1, 0])
        >>> clf.predict_proba(X).round(3)                 # the labels may be flipped
        array([[0.103, 0.897],
               [0.846, 0.154]])
        >>> clf.set_params(vote="satisfaction").predict_proba(X).round(3)  # the vote
        array([[0.019, 0.981],
               [0.904, 0.096]])
        """
        if self._by_satisfaction():
            return self.posterior_.predict_proba(self._validated(X))
        return np.exp(self.predict_log_proba(X))

    def predict_log_proba(self, X):
        """Logarithm of :meth:`predict_proba`.

        Under ``vote="predictive"`` it is computed in log space: finite wherever the label
        noise leaves a label possible, e.g. ``log epsilon`` for a demonstration every formula
        rejects, even where :meth:`predict_proba` rounds that probability to 0.

        Parameters
        ----------
        X : demonstrations, in any format accepted by :meth:`fit`.

        Returns
        -------
        log_proba : ndarray of shape (n_demos, 2)
        """
        traces = self._validated(X)
        if self._by_satisfaction():
            with np.errstate(divide="ignore"):
                return np.log(self.posterior_.predict_proba(traces))
        post = self.posterior_
        return predictive_log_proba(post._masks, post.probabilities, post._truth_words(traces),
                                    self._noise())

    def predict(self, X):
        """The Bayes decision: the class :meth:`predict_proba` favours, acceptable on a tie.

        Parameters
        ----------
        X : demonstrations, in any format accepted by :meth:`fit`.

        Returns
        -------
        y_pred : ndarray of shape (n_demos,)
        """
        proba = self.predict_proba(X)
        return self.classes_[(proba[:, 1] >= proba[:, 0]).astype(int)]

    # ------------------------------------------------------------------ monitoring
    def monitor(self):
        """A runtime monitor of a growing trace under the fitted posterior.

        Returns
        -------
        monitor : bsi_sklearn.monitor.posterior_monitor.PosteriorMonitor
            Feed it one step at a time (``monitor.update(step)``); each step's verdict gives
            the posterior mass of the specifications already satisfied, already violated and
            still open. ``monitor.finish()`` closes the trace.
        """
        from bsi_sklearn.monitor.posterior_monitor import PosteriorMonitor

        check_is_fitted(self)
        return PosteriorMonitor(self.posterior_, binarize=self.binarize)

    def monitor_proba(self, X):
        """Three-valued verdicts over time of every demonstration (see :meth:`monitor`).

        Parameters
        ----------
        X : demonstrations, in any format accepted by :meth:`fit`.

        Returns
        -------
        verdicts : list of ndarray of shape (T_i, 3)
            Row ``t`` is ``(p_satisfied, p_violated, p_open)`` after steps ``0..t`` of a trace
            still running; :meth:`predict_proba` gives the verdict of the closed trace.
        """
        from bsi_sklearn.monitor.posterior_monitor import monitor_traces

        traces = self._validated(X)
        return monitor_traces(self.posterior_, traces)
