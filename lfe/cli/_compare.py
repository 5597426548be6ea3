"""``bsi-lfe compare``'s command line: its arguments, the run and the table it prints.

Light at import: ``bsi-lfe compare --help`` builds its parser from here without loading the
comparison (pandas, scikit-learn, torch); :func:`run` imports the protocol
(:mod:`lfe.compare._protocol`) when the command runs. :mod:`lfe.compare` re-exports
:func:`add_arguments` and :func:`run`.
"""

import io
from pathlib import Path

from lfe._settings import COMPARE_QUICK as QUICK

__all__ = ["add_arguments", "run"]


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
                             f"24 scenarios; --quick: {QUICK['n_scenarios']} simulated, seed 0)")
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


def _option_constraints():
    """The options' constraints (:mod:`bsi_sklearn.param_validation`, imported on a run)."""
    from numbers import Integral

    from bsi_sklearn.param_validation import NONZERO_INTEGER, Interval

    return {
        "n_scenarios": [Interval(Integral, 1, None, closed="left"), None],
        "folds": [Interval(Integral, 2, None, closed="left"), None],
        "seed": [Interval(Integral, 0, None, closed="left")],
        "n_jobs": [None, NONZERO_INTEGER],
        "verbose": [Interval(Integral, 0, None, closed="left")],
    }


def run(args):
    """Run the comparison, write its files to ``--out`` and print the table."""
    from bsi_sklearn.param_validation import check_options
    from lfe.compare import compare
    from lfe.dataset import load_lfe_dataset, make_lfe_dataset

    check_options(args, _option_constraints())
    if args.dataset is not None and args.n_scenarios is not None:
        raise ValueError("give either --dataset or --n-scenarios, not both")
    if args.dataset is not None:
        dataset = load_lfe_dataset(args.dataset)
    elif args.n_scenarios is not None:
        dataset = make_lfe_dataset(args.n_scenarios, random_state=0)
    else:
        dataset = None
    result = compare(dataset, n_splits=args.folds, seed=args.seed, n_jobs=args.n_jobs,
                     quick=args.quick, verbose=args.verbose)
    paths = result.save(args.out)
    print(_console_table(result))
    print(f"files written to {Path(args.out)}: "
          + ", ".join(p.name for p in paths.values()))
    return 0


def _console_table(result):
    """The F1 table, the log loss and Brier, the MAP specifications and the times, printed."""
    from lfe._probability_scores import format_score
    from lfe.compare import format_value

    buf = io.StringIO()
    c = result.config
    print(f"Weighted F1, {c['n_splits']}-fold cross-validation on {c['n_scenarios']} scenarios"
          f"{' (--quick: a smoke test, not the paper setting)' if c['quick'] else ''}", file=buf)
    print("ours = out-of-fold predictions pooled (fold mean ± std); "
          "paper = Shah et al. 2019, Table 'Weighted F1 scores', for reference", file=buf)
    objectives = list(result.f1.columns)
    header = f"{'classifier':<19}" + "".join(f"{mo + ' ours':>22}{mo + ' paper':>10}"
                                              for mo in objectives)
    print(header, file=buf)
    print("-" * len(header), file=buf)
    t = result.table
    for name in t.index:
        line = f"{name:<19}"
        for mo in objectives:
            ours = (f"{t.loc[name, mo]:.3f} ({t.loc[name, mo + ' fold mean']:.2f}"
                    f"±{t.loc[name, mo + ' fold std']:.2f})")
            line += f"{ours:>22}{format_value(t.loc[name, mo + ' paper']):>10}"
        print(line, file=buf)
    print("\nLog loss / Brier of the pooled out-of-fold probabilities (n/a: the row gives "
          "none)", file=buf)
    print(f"{'classifier':<19}" + "".join(f"{mo:>18}" for mo in objectives), file=buf)
    for name in t.index:
        pairs = [f"{format_score(t.loc[name, mo + ' log loss'])} / "
                 f"{format_score(t.loc[name, mo + ' Brier'])}" for mo in objectives]
        print(f"{name:<19}" + "".join(f"{pair:>18}" for pair in pairs), file=buf)
    print("\nMAP specification fitted on every scenario (weighted F1 on them; paper: Prior 2)",
          file=buf)
    for _, row in result.map_f1.iterrows():
        paper = format_value(row["paper"])
        print(f"  {row['classifier']:<17} {row['objective']}  {row['f1']:.3f}"
              f"{'  paper ' + paper if paper else ''}   {row['map_specification']}", file=buf)
    print("\nSeconds per fold (fit / predict):", file=buf)
    for name, row in result.times.iterrows():
        print(f"  {name:<19} {row['fit_s_mean']:8.2f} / {row['predict_s_mean']:.3f}", file=buf)
    print(f"\nWhole run: {result.elapsed:.1f} s wall clock", file=buf)
    return buf.getvalue().rstrip("\n")
