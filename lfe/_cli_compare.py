"""``bsi-lfe compare``'s arguments, in a module that imports nothing heavy.

``bsi-lfe compare --help`` builds its parser from here without loading the comparison
(pandas, scikit-learn, torch); :func:`run` imports :mod:`lfe.compare` when the command runs.
"""

__all__ = ["QUICK", "add_arguments", "run"]

#: ``--quick``: the simulated scenarios (unless ``--dataset``) and the folds.
QUICK = dict(n_scenarios=8, n_splits=2)


def add_arguments(parser):
    """Arguments of ``bsi-lfe compare``."""
    parser.add_argument("--out", default="results", metavar="DIR",
                        help="output directory (default: results)")
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK['n_scenarios']} simulated scenarios (unless --dataset), "
                             f"{QUICK['n_splits']} folds, small baselines and short MCMC runs: "
                             "a smoke test, not the paper's result")
    parser.add_argument("--dataset", metavar="DIR", default=None,
                        help="a dataset written by 'bsi-lfe simulate' (default: the built-in "
                             "24 scenarios)")
    parser.add_argument("--n-scenarios", type=int, default=None, metavar="N",
                        help="simulate N scenarios (seed 0) instead of the built-in dataset")
    parser.add_argument("--folds", type=int, default=None, metavar="K",
                        help="cross-validation folds (default: 4, the paper's; 2 with --quick)")
    parser.add_argument("--seed", type=int, default=0,
                        help="seed of the folds and of every model (default: 0)")
    parser.add_argument("--n-jobs", type=int, default=None,
                        help="parallel fitting processes (default: 1; -1: every core); the "
                             "tables do not depend on it")
    parser.add_argument("--verbose", type=int, default=1,
                        help="0: no progress bar (default: 1)")


def run(args):
    """Run the comparison (:func:`lfe.compare.run`)."""
    from lfe import compare

    return compare.run(args)
