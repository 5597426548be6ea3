"""``bsi-lfe simulate``: simulate, annotate and save a dataset of LFE missions."""

import math
from pathlib import Path

from lfe.dataset import make_lfe_dataset

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


def _check_args(args):
    # Checked before simulating, so a typo fails at once and writes nothing.
    if args.n_scenarios < 1:
        raise ValueError(f"--n-scenarios must be a positive integer, got {args.n_scenarios}")
    if not 0 <= args.seed < 2**32:
        raise ValueError(f"--seed must be an integer in [0, 2**32), got {args.seed}")
    if not 0.0 <= args.noise <= 1.0:
        raise ValueError(f"--noise must be a number in [0, 1], got {args.noise}")
    if not (math.isfinite(args.time_noise) and args.time_noise >= 0):
        raise ValueError(f"--time-noise must be a finite number >= 0, got {args.time_noise}")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} is a file, not a directory")
    return out


def run(args):
    """Simulate the dataset, write it to ``args.out`` and print a summary."""
    out = _check_args(args)
    dataset = make_lfe_dataset(args.n_scenarios, random_state=args.seed, noise=args.noise,
                               time_noise=args.time_noise)
    path = dataset.save(out)
    print(repr(dataset))
    print(f"written to {path}")
    return 0
