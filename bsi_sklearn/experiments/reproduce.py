"""``bsi reproduce synthetic|dinner|active``: the experiments from the command line."""

from __future__ import annotations

from numbers import Integral

__all__ = ["add_arguments", "run"]

EXPERIMENTS = ("synthetic", "dinner", "active")


def _checked(convert, constraints):
    """:func:`~bsi_sklearn.param_validation.option_type`, built when an option is parsed.

    ``bsi_sklearn.param_validation`` loads numpy, which ``bsi reproduce --help`` does not need.
    """

    def parse(text):
        from bsi_sklearn.param_validation import option_type

        return option_type(convert, constraints())(text)

    parse.__name__ = convert.__name__  # argparse's "invalid int value: ..."
    return parse


def _positive():
    from bsi_sklearn.param_validation import Interval

    return [Interval(Integral, 1, None, closed="left")]


def _nonzero():
    from bsi_sklearn.param_validation import NONZERO_INTEGER

    return [NONZERO_INTEGER]


_positive_int = _checked(int, _positive)
_n_jobs = _checked(int, _nonzero)


def add_arguments(parser):
    """Add the ``reproduce`` arguments to ``parser``."""
    parser.add_argument("experiment", choices=EXPERIMENTS,
                        help="synthetic: POI/threat Scenarios 1-3; dinner: the dinner table; "
                             "active: entropy sampling vs random queries (Scenario 1)")
    parser.add_argument("--out", default=None,
                        help="output folder (default: ./bsi_reproduce/<experiment>)")
    parser.add_argument("--quick", action="store_true",
                        help="small sizes and few repeats: well under a minute")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    parser.add_argument("--n-jobs", type=_n_jobs, default=-1,
                        help="fits run in this many threads (default: -1, all cores; not 0)")
    parser.add_argument("--repeats", type=_positive_int, default=None,
                        help="random draws of the training set per size; active: seeds "
                             "(default: the experiment's)")
    parser.add_argument("--sizes", type=_positive_int, nargs="+", default=None,
                        help="training-set sizes (default: the experiment's)")
    parser.add_argument("--no-supervised", action="store_true",
                        help="skip the supervised variant (positives and negatives)")
    parser.add_argument("--no-alt-priors", action="store_true",
                        help="synthetic: skip the rerun of Priors 2 and 3 with p_part=0.7 and "
                             "n_new=0.5")
    parser.add_argument("--verbose", type=int, default=1,
                        help="0: silent; 1 (default): progress bars on a terminal and the "
                             "claims table")


def run(args):
    """Run the chosen experiment and print its claims table; returns the exit status."""
    from bsi_sklearn.experiments import run_dinner, run_synthetic

    out = args.out if args.out is not None else f"bsi_reproduce/{args.experiment}"
    kwargs = {}
    if args.experiment == "active":
        from bsi_sklearn.experiments.active import run_active

        result = run_active(out, quick=args.quick, n_seeds=args.repeats,
                            random_state=args.seed, verbose=args.verbose)
        return _print(args, result, out)
    if args.experiment == "synthetic":
        runner = run_synthetic
        kwargs["alternative_priors"] = not args.no_alt_priors
    else:
        runner = run_dinner
    result = runner(out, quick=args.quick, sizes=args.sizes, n_repeats=args.repeats,
                    supervised=not args.no_supervised, n_jobs=args.n_jobs,
                    random_state=args.seed, verbose=args.verbose, **kwargs)
    return _print(args, result, out)


def _print(args, result, out):
    import pandas as pd

    if args.verbose:
        claims = result.claims[["id", "measured", "status"]]
        with pd.option_context("display.max_colwidth", 90, "display.width", 160):
            print(claims.to_string(index=False))
        n_pass = int((result.claims["status"] == "PASS").sum())
        n_fits = result.config["n_fits"] + result.config.get("n_alt_priors_fits", 0)
        print(f"\n{n_pass}/{len(claims)} claims pass; {n_fits} fits in "
              f"{result.elapsed:.1f} s; files in {out}/:")
        for path in result.files:
            print(f"  {path.name}")
    return 0
