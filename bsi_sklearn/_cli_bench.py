"""``bsi bench``: run the benchmark suite of a source checkout (``benchmarks/run.py``).

The benchmarks are not part of the installed package: they live next to it in the repository
(the package is installed editable for development). This module finds ``benchmarks/run.py``
from the package's own path and runs it in-process with the parsed options.
"""

import importlib.util
from pathlib import Path

import bsi_sklearn

__all__ = ["add_arguments", "run", "benchmarks_dir"]


def add_arguments(parser):
    """Options of the benchmark suite (shared by ``bsi bench`` and ``benchmarks/run.py``).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The parser to extend.

    Returns
    -------
    parser : argparse.ArgumentParser

    Examples
    --------
    >>> import argparse
    >>> p = add_arguments(argparse.ArgumentParser())
    >>> args = p.parse_args(["--quick", "--only", "exact,predict"])
    >>> args.quick, args.only, args.out
    (True, 'exact,predict', None)
    """
    parser.add_argument("--quick", action="store_true",
                        help="shrink every size (about a minute; used by the tests); the "
                             "numbers are not the recorded ones")
    parser.add_argument("--only", default=None, metavar="NAME[,NAME...]",
                        help="run only these benchmarks (comma-separated; see --list)")
    parser.add_argument("--repeats", type=int, default=None,
                        help="timed calls per measurement, the median is reported "
                             "(default 7, --quick 2)")
    parser.add_argument("--out", default=None, metavar="DIR",
                        help="folder for RESULTS.md, results.json and figures/ "
                             "(default: the benchmarks/ folder itself)")
    parser.add_argument("--no-install", action="store_true",
                        help="never run `npm install` for the webppl reference "
                             "(implied by --quick)")
    parser.add_argument("--list", action="store_true", help="list the benchmarks and exit")
    parser.add_argument("--note", default=None, metavar="TEXT",
                        help="a paragraph for the header of RESULTS.md (e.g. the conditions "
                             "of the run)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


def benchmarks_dir(root=None):
    """The ``benchmarks/`` folder of the source checkout this package was imported from.

    Parameters
    ----------
    root : str or Path, default=None
        Repository root to look in; ``None`` uses the parent folder of the ``bsi_sklearn``
        package (an editable install or a source checkout).

    Returns
    -------
    path : Path
        The folder holding ``run.py``.

    Raises
    ------
    FileNotFoundError
        When there is no ``benchmarks/run.py`` there (e.g. a wheel install: the benchmarks
        ship with the repository, not with the package).

    Examples
    --------
    >>> benchmarks_dir("/nonexistent")
    Traceback (most recent call last):
    ...
    FileNotFoundError: bsi bench needs the benchmarks/ folder of a bsi-sklearn source ...
    """
    root = Path(bsi_sklearn.__file__).resolve().parent.parent if root is None else Path(root)
    folder = root / "benchmarks"
    if not (folder / "run.py").is_file():
        raise FileNotFoundError(
            f"bsi bench needs the benchmarks/ folder of a bsi-sklearn source checkout, and "
            f"{folder / 'run.py'} does not exist (the benchmarks are not installed with the "
            "package): clone the repository, `pip install -e .` it, and run `bsi bench` or "
            "`python benchmarks/run.py` there"
        )
    return folder


def _load_runner(folder):
    spec = importlib.util.spec_from_file_location("_bsi_benchmarks_run", folder / "run.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run(args):
    """Run the suite with the parsed options; returns its exit status."""
    runner = _load_runner(benchmarks_dir())
    return runner.run_suite(args, prog="bsi bench")
