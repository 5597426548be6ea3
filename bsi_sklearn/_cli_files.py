"""The files of the ``bsi`` command: inputs read by format, outputs checked and named uniquely.

Every problem with a path is a ``ValueError`` naming it (the command prints it on one line and
exits with status 2); outputs are named from the inputs' names and the demonstrations' ids,
made unique, so that no output overwrites another.
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["FORMATS", "add_format_argument", "check_input", "check_output_dir",
           "check_output_file", "file_safe", "load_demonstrations", "unique_names",
           "unique_stems"]

#: File formats by extension.
FORMATS = {".csv": "csv", ".trace": "trace"}


def add_format_argument(parser):
    """``--format``: how to read the FILEs (by default, from their extension)."""
    parser.add_argument("--format", choices=["auto", *FORMATS.values()], default="auto",
                        help="how to read the FILEs: by extension (auto: .csv is long-format "
                             "CSV, .trace the samples2LTL / Scarlet format; any other "
                             "extension is an error), or all as csv or trace "
                             "(default: %(default)s)")


def check_input(path):
    """``path`` as a Path, when it is an existing regular file.

    Raises
    ------
    ValueError
        When ``path`` is missing, a folder or not a regular file.
    """
    p = Path(path)
    if not p.exists():
        raise ValueError(f"{path}: no such file")
    if p.is_dir():
        raise ValueError(f"{path}: is a folder, not a file")
    if not p.is_file():
        raise ValueError(f"{path}: not a regular file")
    return p


def _format_of(path, fmt):
    if fmt != "auto":
        return fmt
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"{path}: the extension {suffix or '(none)'!r} does not say the "
                         "format; name the file .csv (long-format CSV) or .trace "
                         "(samples2LTL / Scarlet), or pass --format csv / --format trace")
    return FORMATS[suffix]


def load_demonstrations(path, fmt="auto"):
    """Read one input file.

    Parameters
    ----------
    path : str
    fmt : {"auto", "csv", "trace"}, default="auto"
        ``auto`` decides by the extension (``.csv`` or ``.trace``).

    Returns
    -------
    X : list of DataFrame
    y : ndarray or None
        Labels (``None`` for a CSV file without a ``label`` column).
    target : LTL formula or None
        The target formula of a ``.trace`` file, when it has one.
    ids : list
        The demonstrations' ids: the CSV's ``demo_id`` values, or the position (from 0) in a
        ``.trace`` file (positives, then negatives).
    """
    from bsi_sklearn import io

    check_input(path)
    if _format_of(path, fmt) == "csv":
        X, y, ids = io.read_traces_csv(path, return_ids=True)
        return X, y, None, list(ids)
    X, y, target = io.load_trace_file(path)
    return X, y, target, list(range(len(X)))


def check_output_file(path, option):
    """``path`` as a Path when a file can be written there (its folder exists).

    Raises
    ------
    ValueError
        Naming ``option``, when ``path`` is a folder or its folder is missing or a file.
    """
    p = Path(path)
    if str(path) == "":
        raise ValueError(f"{option}: the path is empty")
    if p.is_dir():
        raise ValueError(f"{option} {path}: is a folder; give a file name")
    if not p.parent.is_dir():
        what = "is a file, not a folder" if p.parent.exists() else "does not exist"
        raise ValueError(f"{option} {path}: cannot write there, {p.parent} {what}")
    return p


def check_output_dir(path, option):
    """``path`` as a Path of an existing folder (made when missing, with its parents).

    Raises
    ------
    ValueError
        Naming ``option``, when ``path`` or one of its parents is a file, or it cannot be made.
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise ValueError(f"{option} {path}: is a file, not a folder")
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"{option} {path}: cannot make the folder ({exc.strerror})") from None
    return p


def file_safe(text):
    """``text`` with every character but letters, digits, ``.``, ``-`` and ``_`` as ``_``.

    Examples
    --------
    >>> file_safe("run 3/a")
    'run_3_a'
    """
    return re.sub(r"[^A-Za-z0-9._-]", "_", str(text)) or "_"


def unique_names(names):
    """File-safe versions of ``names``, made unique by adding ``-<position>`` to clashes.

    Examples
    --------
    >>> unique_names(["a", "b/c", "b_c", 7])
    ['a', 'b_c-1', 'b_c-2', '7']
    """
    safe = [file_safe(n) for n in names]
    count = {}
    for s in safe:
        count[s] = count.get(s, 0) + 1
    return [s if count[s] == 1 else f"{s}-{k}" for k, s in enumerate(safe)]


def unique_stems(paths):
    """A distinct, file-safe name for every input path, as short as can be.

    The stem (``demos``) when no other input has it; else the name with its extension
    (``demos_csv``), then with as many parent folders as tell them apart (``a_demos_csv``).

    Raises
    ------
    ValueError
        When the same file is given twice.

    Examples
    --------
    >>> unique_stems(["x/demos.csv", "y/demos.csv", "other.trace"])
    ['x_demos_csv', 'y_demos_csv', 'other']
    """
    resolved = [Path(p).resolve() for p in paths]
    for k, r in enumerate(resolved):
        if r in resolved[:k]:
            raise ValueError(f"{paths[k]}: the file is given twice")

    def label(r, level):
        if level == 0:
            return file_safe(r.stem)
        parts = [*r.parent.parts[1:][len(r.parent.parts) - level:], r.name]
        return file_safe("_".join(parts).replace(".", "_"))

    out = [label(r, 0) for r in resolved]
    for level in range(1, max(len(r.parts) for r in resolved) + 1):
        clash = {s for s in out if out.count(s) > 1}
        if not clash:
            break
        out = [label(r, level) if s in clash else s for r, s in zip(resolved, out)]
    return unique_names(out)
