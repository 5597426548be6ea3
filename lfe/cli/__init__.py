"""The ``bsi-lfe`` command line: ``simulate``, ``compare``, ``study`` and ``report`` subcommands.

Each subcommand's arguments live in a light module exposing ``add_arguments(parser)`` and
``run(args)`` (``lfe.cli._*``: nothing heavy imported, so that ``--help`` is quick); ``run``
imports the subcommand's real module when it runs. The real modules never import the light
ones back: the settings both need (``--quick`` sizes, the study's defaults) live in
``lfe._settings``. This file only wires them, importing a module when its subcommand is chosen.
"""

import sys

from bsi_sklearn.cli.support import build_parser as build_parser_from
from bsi_sklearn.cli.support import run_command

__all__ = ["main"]

# name -> (module, help)
SUBCOMMANDS = {
    "simulate": ("lfe.cli._simulate", "simulate and annotate a dataset of LFE missions"),
    "compare": ("lfe.cli._compare",
                "BSI vs the LSTM baselines on the LFE missions (the paper's F1 table)"),
    "study": ("lfe.cli._study",
              "learning curves of BSI and the networks with 95% intervals over repeats"),
    "report": ("lfe.cli._report",
               "interpretability report of the MAP specification per mission objective"),
}


def build_parser(argv=None):
    """The argument parser of ``bsi-lfe`` (subcommand modules add their own arguments).

    Parameters
    ----------
    argv : list of str, default=None
        The arguments to be parsed: only the module of the subcommand they name is imported.
        ``None`` imports them all.
    """
    return build_parser_from(
        "bsi-lfe", "Large-force-exercise domain of Bayesian Specification Inference.",
        SUBCOMMANDS, argv
    )


def main(argv=None):
    """Entry point of the ``bsi-lfe`` console script; returns the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    return run_command(build_parser(argv), argv)
