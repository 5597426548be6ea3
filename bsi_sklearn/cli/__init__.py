"""The ``bsi`` command line: ``fit``, ``monitor``, ``reproduce`` and ``compile`` subcommands.

Each subcommand lives in its own module exposing ``add_arguments(parser)`` and ``run(args)``;
this file only wires them, importing a module when its subcommand runs.
"""

import sys

from bsi_sklearn.cli.support import build_parser as build_parser_from
from bsi_sklearn.cli.support import run_command

__all__ = ["main"]

# name -> (module, help)
SUBCOMMANDS = {
    "fit": ("bsi_sklearn.cli._fit", "fit BSI on trace files and print the posterior"),
    "monitor": ("bsi_sklearn.cli._monitor",
                "replay demonstrations against a saved posterior: verdicts over time, plots"),
    "reproduce": ("bsi_sklearn.experiments.reproduce",
                  "reproduce the paper's synthetic-domain or dinner-table experiments"),
    "compile": ("bsi_sklearn.compile",
                "compile the numba kernels into numba's cache (once after installing)"),
}


def build_parser(argv=None):
    """The argument parser of ``bsi`` (subcommand modules add their own arguments).

    Parameters
    ----------
    argv : list of str, default=None
        The arguments to be parsed: only the module of the subcommand they name is imported.
        ``None`` imports them all.
    """
    return build_parser_from(
        "bsi", "Bayesian Specification Inference from demonstrations.", SUBCOMMANDS, argv
    )


def main(argv=None):
    """Entry point of the ``bsi`` console script; returns the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    return run_command(build_parser(argv), argv)
