"""``bsi-lfe report``'s arguments, in a module that imports nothing heavy.

``bsi-lfe report --help`` builds its parser from here without loading BSI, the LFE simulator
or matplotlib; :func:`run` imports :mod:`lfe.report` when the command runs. The choices are
written out here; ``tests/cli/test_cli_help.py`` checks them against the modules they come from.
"""

from lfe._settings import REPORT_QUICK as QUICK

__all__ = ["LIKELIHOOD_CHOICES", "OBJECTIVE_CHOICES", "PRIOR_CHOICES",
           "PROPOSITION_SET_CHOICES", "add_arguments", "run"]

#: ``lfe.annotate.MISSION_OBJECTIVES``.
OBJECTIVE_CHOICES = ("MO1", "MO2", "MO3")
#: The keys of ``lfe.propositions.PROPOSITION_SETS``.
PROPOSITION_SET_CHOICES = ("paper", "extended")
#: ``bsi_sklearn.model.priors.PRIORS`` and ``bsi_sklearn.model.likelihood.LIKELIHOODS``.
PRIOR_CHOICES = ("linear_chain", "sets_of_chains", "forest")
LIKELIHOOD_CHOICES = ("cb", "ci", "calibrated")


def add_arguments(parser):
    """Arguments of ``bsi-lfe report``."""
    parser.add_argument("--out", default="lfe_report", metavar="DIR",
                        help="output directory (default: lfe_report)")
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK['n_scenarios']} simulated scenarios (unless "
                             "--dataset) and a short MCMC run: a smoke test, not the paper's "
                             "result")
    parser.add_argument("--dataset", metavar="DIR", default=None,
                        help="a dataset written by 'bsi-lfe simulate' (default: the built-in "
                             f"24 scenarios; --quick: {QUICK['n_scenarios']} simulated, seeded "
                             "by --seed)")
    parser.add_argument("--objectives", nargs="+", default=list(OBJECTIVE_CHOICES),
                        metavar="MO", help="objectives to explain (default: all)")
    parser.add_argument("--propositions", choices=PROPOSITION_SET_CHOICES, default="paper",
                        help="proposition set (default: %(default)s)")
    parser.add_argument("--prior", choices=PRIOR_CHOICES, default="sets_of_chains",
                        help="prior over the order of subtasks (default: %(default)s)")
    parser.add_argument("--likelihood", choices=LIKELIHOOD_CHOICES, default="cb",
                        help="likelihood (default: %(default)s)")
    parser.add_argument("--inference", choices=["auto", "exact", "mcmc"], default="auto",
                        help="exact enumeration, MCMC, or auto: exact when the support is "
                             "small enough (default: %(default)s; --quick: always auto)")
    parser.add_argument("--n-samples", type=int, default=10_000,
                        help="MCMC samples per chain, when sampling (default: %(default)s; "
                             f"--quick: {QUICK['n_samples']})")
    parser.add_argument("--seed", type=int, default=0,
                        help="random seed (default: %(default)s)")
    parser.add_argument("--n-jobs", type=int, default=None,
                        help="MCMC chains run in parallel threads (default: 1; -1: every "
                             "core)")


def run(args):
    """Fit, explain and write the reports (:func:`lfe.report.run`)."""
    from lfe import report

    return report.run(args)
