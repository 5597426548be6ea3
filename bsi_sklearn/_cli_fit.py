"""``bsi fit FILE...``: fit BSI on trace files and print the MAP specification and posterior."""

from numbers import Integral
from pathlib import Path

import numpy as np

from bsi_sklearn.classifier import BSIClassifier
from bsi_sklearn.likelihood import LIKELIHOODS
from bsi_sklearn.param_validation import Interval, check_options
from bsi_sklearn.priors import PRIORS

__all__ = ["add_arguments", "run"]


def add_arguments(parser):
    """Arguments of ``bsi fit``."""
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help=".trace files (samples2LTL / Scarlet) or long-format CSV files")
    parser.add_argument("--prior", choices=PRIORS, default="sets_of_chains")
    parser.add_argument("--likelihood", choices=LIKELIHOODS, default="cb")
    parser.add_argument("--inference", choices=["auto", "exact", "mcmc"], default="auto")
    parser.add_argument("--n-samples", type=int, default=10_000)
    parser.add_argument("--top", type=int, default=5, help="posterior entries to print")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--save", default=None, metavar="JSON",
                        help="write the posterior as JSON (Posterior.to_json); with several "
                             "FILEs, each one's stem is added: posterior_<stem>.json")


_OPTION_CONSTRAINTS = {
    "n_samples": BSIClassifier._parameter_constraints["n_samples"],
    "top": [Interval(Integral, 1, None, closed="left")],
    "seed": [Interval(Integral, 0, 2**32 - 1, closed="both")],
}


def _load(path):
    from bsi_sklearn import io

    if str(path).endswith(".csv"):
        X, y = io.read_traces_csv(path)
        return X, y, None
    return io.load_trace_file(path)


def run(args):
    """Fit on every file (one model per file) and print the results."""
    check_options(args, _OPTION_CONSTRAINTS)
    for path in args.files:
        X, y, target = _load(path)
        clf = BSIClassifier(prior=args.prior, likelihood=args.likelihood,
                            inference=args.inference, n_samples=args.n_samples,
                            random_state=args.seed)
        y = np.ones(len(X), dtype=int) if y is None else np.asarray(y)
        clf.fit(X, y)
        print(f"== {path}: {len(X)} demonstrations ({int(y.sum())} acceptable), "
              f"{clf.n_features_in_} propositions, {clf.inference_} inference")
        if target is not None:
            print(f"target     : {target}")
        print(f"MAP        : {clf.map_specification_.to_ltl()}")
        print(f"accuracy   : {clf.score(X, y):.3f} (training set)")
        frame = clf.posterior_.to_frame(k=args.top)[["probability", "ltl"]]
        print(frame.to_string(formatters={"probability": "{:.4f}".format}))
        if args.save is not None:
            out = Path(args.save)
            if len(args.files) > 1:
                out = out.with_name(f"{out.stem}_{Path(path).stem}{out.suffix}")
            clf.posterior_.to_json(out)
            print(f"saved      : {out}")
    return 0
