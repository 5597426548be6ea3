"""The ``bsi-lfe`` command line: ``simulate``, ``compare`` and ``report`` subcommands.

Each subcommand lives in its own module exposing ``add_arguments(parser)`` and ``run(args)``;
this file only wires them, importing a module when the parser is built.
"""

import argparse
import importlib
import sys

__all__ = ["main"]

# name -> (module, help)
SUBCOMMANDS = {
    "simulate": ("lfe._cli_simulate", "simulate and annotate a dataset of LFE missions"),
    "compare": ("lfe.compare",
                "BSI vs the LSTM baselines on the LFE missions (the paper's F1 table)"),
    "report": ("lfe.report",
               "interpretability report of the MAP specification per mission objective"),
}


def build_parser():
    """The argument parser of ``bsi-lfe`` (subcommand modules add their own arguments)."""
    parser = argparse.ArgumentParser(
        prog="bsi-lfe",
        description="Large-force-exercise domain of Bayesian Specification Inference.",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for name, (module_name, help_) in SUBCOMMANDS.items():
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name != module_name:  # a real import error inside the module
                raise
            continue
        p = sub.add_parser(name, help=help_, description=help_)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv=None):
    """Entry point of the ``bsi-lfe`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        status = args._run(args)
    except (ValueError, FileNotFoundError) as exc:
        print(f"bsi-lfe {args.command}: error: {exc}", file=sys.stderr)
        return 2
    return 0 if status is None else int(status)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
