"""The ``bsi`` command line: ``fit``, ``reproduce`` and ``bench`` subcommands.

Each subcommand lives in its own module exposing ``add_arguments(parser)`` and ``run(args)``;
this file only wires them, importing a module when its subcommand runs.
"""

import argparse
import importlib
import sys

__all__ = ["main"]

# name -> (module, help)
SUBCOMMANDS = {
    "fit": ("bsi_sklearn._cli_fit", "fit BSI on trace files and print the posterior"),
    "reproduce": ("bsi_sklearn.experiments.reproduce",
                  "reproduce the paper's synthetic-domain or dinner-table experiments"),
    "bench": ("bsi_sklearn._cli_bench", "run the benchmark suite in benchmarks/"),
}


def build_parser():
    """The argument parser of ``bsi`` (subcommand modules add their own arguments)."""
    parser = argparse.ArgumentParser(
        prog="bsi", description="Bayesian Specification Inference from demonstrations."
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for name, (module_name, help_) in SUBCOMMANDS.items():
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue
        p = sub.add_parser(name, help=help_, description=help_)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv=None):
    """Entry point of the ``bsi`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        status = args._run(args)
    except (ValueError, FileNotFoundError) as exc:
        print(f"bsi {args.command}: error: {exc}", file=sys.stderr)
        return 2
    return 0 if status is None else int(status)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
