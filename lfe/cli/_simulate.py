"""``bsi-lfe simulate``: simulate, annotate and save a dataset of LFE missions, or checksum it.

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
    parser.add_argument("--out", metavar="DIR",
                        help="output directory (CSV tables and JSON, see LFEDataset.save); "
                             "required unless --checksum")
    parser.add_argument("--checksum", action="store_true",
                        help="print the sha256 of the dataset (the built-in one by default) "
                             "and of repeat 0 of 'bsi-lfe study --seed SEED' (about 30 s): "
                             "machines that print the same digests simulate the same "
                             "missions, bit for bit")


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
    if args.out is None:
        if not getattr(args, "checksum", False):
            raise ValueError("--out DIR is required (unless --checksum)")
        return None
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"--out {out} is a file, not a directory")
    return out


def _is_default(args):
    return (args.n_scenarios, args.seed, args.noise, args.time_noise) == (24, 0, 0.04, 10.0)


def _print_checksums(args, dataset):
    from lfe.checksum import RECORDED, dataset_digest, machine, study_repeat_digest

    def verdict(what, digest, default):
        if not default or RECORDED.get(what) is None:
            return ""
        return ("  (the recorded value)" if digest == RECORDED[what] else
                f"  DIFFERS from the recorded {RECORDED[what]}")

    print(f"sha256 of the missions ({machine()}):")
    digest = dataset_digest(dataset)
    print(f"dataset         {digest}{verdict('dataset', digest, _is_default(args))}")
    print(f"                make_lfe_dataset({args.n_scenarios}, random_state={args.seed}, "
          f"noise={args.noise:g}, time_noise={args.time_noise:g}): {dataset!r}")
    digest, summary = study_repeat_digest(args.seed, 0)
    print(f"study repeat 0  {digest}{verdict('study repeat 0', digest, args.seed == 0)}")
    print(f"                {summary}")


def run(args):
    """Simulate the dataset; write it to ``args.out`` and/or print its checksums."""
    from lfe.dataset import make_lfe_dataset

    out = _check_args(args)
    dataset = make_lfe_dataset(args.n_scenarios, random_state=args.seed, noise=args.noise,
                               time_noise=args.time_noise)
    if out is not None:
        path = dataset.save(out)
        print(repr(dataset))
        print(f"written to {path}")
    if getattr(args, "checksum", False):
        _print_checksums(args, dataset)
    return 0
