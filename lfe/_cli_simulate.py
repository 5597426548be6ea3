"""``bsi-lfe simulate``: simulate, annotate and save a dataset of LFE missions.

Nothing heavy is imported until the command runs (``--help`` stays quick).
"""

from pathlib import Path

__all__ = ["add_arguments", "run"]


def add_arguments(parser):
    """Arguments of ``bsi-lfe simulate``."""
    parser.add_argument("--n-scenarios", type=int, default=24,
                        help="number of scenarios (default: 24, as in the paper)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    parser.add_argument("--noise", type=float, default=0.04,
                        help="probability the commander's verdict on an objective is flipped "
                             "(default: 0.04)")
    parser.add_argument("--time-noise", type=float, default=10.0,
                        help="standard deviation (s) of the marked phase times (default: 10)")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="output directory (CSV tables and JSON, see LFEDataset.save)")


def _option_constraints():
    from numbers import Integral

    from bsi_sklearn.param_validation import Interval
    from lfe.annotate import _ANNOTATE_CONSTRAINTS

    return {
        "n_scenarios": [Interval(Integral, 1, None, closed="left")],
        "seed": [Interval(Integral, 0, 2**32 - 1, closed="both")],
        "noise": _ANNOTATE_CONSTRAINTS["noise"],
        "time_noise": _ANNOTATE_CONSTRAINTS["time_noise"],
    }


def _check_args(args):
    from bsi_sklearn.param_validation import check_options

    # Checked before simulating, so a typo fails at once and writes nothing.
    check_options(args, _option_constraints())
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} is a file, not a directory")
    return out


def run(args):
    """Simulate the dataset, write it to ``args.out`` and print a summary."""
    from lfe.dataset import make_lfe_dataset

    out = _check_args(args)
    dataset = make_lfe_dataset(args.n_scenarios, random_state=args.seed, noise=args.noise,
                               time_noise=args.time_noise)
    path = dataset.save(out)
    print(repr(dataset))
    print(f"written to {path}")
    return 0
