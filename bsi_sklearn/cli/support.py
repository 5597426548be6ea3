"""Shared plumbing of the ``bsi`` and ``bsi-lfe`` command lines: parser wiring and exit status.

Each subcommand lives in its own module exposing ``add_arguments(parser)`` and ``run(args)``;
a command line is a table ``name -> (module, help)`` wired by :func:`build_parser` and run by
:func:`run_command`. ``lfe.cli`` builds ``bsi-lfe`` from the same two functions.
"""

import argparse
import importlib
import importlib.util
import sys

__all__ = ["build_parser", "run_command"]


def build_parser(prog, description, subcommands, argv=None):
    """An argument parser with one subparser per importable subcommand module.

    A subcommand whose module is absent (an optional part not installed) is left out; an
    import error inside a present module propagates.

    Parameters
    ----------
    prog : str
        Name of the command (``bsi``, ``bsi-lfe``).
    description : str
        One-line description shown by ``--help``.
    subcommands : dict
        ``name -> (module_name, help)``; the module exposes ``add_arguments(parser)`` and
        ``run(args)``.
    argv : list of str, default=None
        The arguments about to be parsed: only the module of the subcommand they name is
        imported (the others are listed by their help line), so that ``--help`` and each
        command start quickly. ``None`` imports every module.

    Returns
    -------
    parser : argparse.ArgumentParser
        The parser; each subparser sets ``args._run`` to its module's ``run``.

    Examples
    --------
    >>> parser = build_parser("bsi", "demo", {"fit": ("bsi_sklearn.cli._fit", "fit files"),
    ...                                       "gone": ("no_such_module_xyz", "left out")})
    >>> parser.parse_args(["fit", "a.trace"]).files
    ['a.trace']
    >>> "{fit}" in parser.format_usage()
    True
    """
    chosen = None
    if argv is not None:
        chosen = next((a for a in argv if not a.startswith("-")), None)
    parser = argparse.ArgumentParser(prog=prog, description=description)
    sub = parser.add_subparsers(dest="command", required=True)
    for name, (module_name, help_) in subcommands.items():
        load = argv is None or name == chosen
        if load:
            try:
                module = importlib.import_module(module_name)
            except ModuleNotFoundError as exc:
                if exc.name != module_name:
                    raise
                continue
        elif not _present(module_name):
            continue
        # argparse fills %(...)s in help texts: a bare % (as in "95% intervals") is escaped.
        p = sub.add_parser(name, help=help_.replace("%", "%%"), description=help_)
        if load:
            module.add_arguments(p)
            p.set_defaults(_run=module.run)
    return parser


def _present(module_name):
    """Whether ``module_name`` can be imported, without importing it (only its packages)."""
    try:
        return importlib.util.find_spec(module_name) is not None
    except ModuleNotFoundError:
        return False


def run_command(parser, argv=None):
    """Parse ``argv``, run the chosen subcommand and return its exit status.

    A ``ValueError`` (bad input) or an ``OSError`` (a file that cannot be read or written)
    prints one line ``prog command: error: ...``, naming the file, on stderr and gives
    status 2, as argparse does for bad arguments.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        A parser made by :func:`build_parser`.
    argv : list of str, default=None
        The arguments; ``None`` reads ``sys.argv[1:]``.

    Returns
    -------
    status : int
        The subcommand's exit status (0 when it returns ``None``), 2 on bad input.
    """
    args = parser.parse_args(argv)
    try:
        status = args._run(args)
    except ValueError as exc:
        print(f"{parser.prog} {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"{parser.prog} {args.command}: error: {_os_error(exc)}", file=sys.stderr)
        return 2
    return 0 if status is None else int(status)


def _os_error(exc):
    """``file: reason`` for an OSError (its text when it names no file)."""
    if exc.filename is None or exc.strerror is None:
        return str(exc)
    return f"{exc.filename}: {exc.strerror.lower()}"
