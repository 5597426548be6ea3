"""The files of the ``bsi`` command: inputs read by format, outputs checked and named uniquely.

Every problem with a path is a ``ValueError`` naming it (the command prints it on one line and
exits with status 2); outputs are named from the inputs' names and the demonstrations' ids,
made unique, so that no output overwrites another.
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["FORMATS", "EVENT_LOG_CASE_ID", "add_format_argument", "input_format",
           "check_input", "check_output_dir", "check_output_file", "file_safe",
           "load_demonstrations", "unique_names", "unique_stems"]

#: File formats by extension (``.xes.gz`` too is an event log).
FORMATS = {".csv": "csv", ".trace": "trace", ".xes": "event-log"}
#: pm4py's case id column: a ``.csv`` whose header has it is read as an event log.
EVENT_LOG_CASE_ID = "case:concept:name"


def add_format_argument(parser, event_logs=False):
    """``--format``: how to read the FILEs (by default, from their extension)."""
    choices = ["auto", *dict.fromkeys(FORMATS.values())]
    if not event_logs:
        choices.remove("event-log")
    parser.add_argument("--format", choices=choices, default="auto",
                        help="how to read the FILEs: by extension (auto: .csv is long-format "
                             "CSV, .trace the samples2LTL / Scarlet format"
                             + ("; .xes / .xes.gz an event log, and so is a .csv whose header "
                                "has the case id column (--case-id)" if event_logs else "")
                             + "; any other extension is an error), or all as "
                             + ("csv, trace or event-log" if event_logs else "csv or trace")
                             + " (default: %(default)s)")


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


def _format_of(path, fmt, case_id=None):
    if fmt != "auto":
        return fmt
    suffix = Path(path).suffix.lower()
    if case_id is not None and str(path).lower().endswith(".xes.gz"):
        return "event-log"
    if case_id is not None and suffix == ".csv" and _has_column(path, case_id):
        return "event-log"
    if suffix not in FORMATS or (case_id is None and FORMATS[suffix] == "event-log"):
        raise ValueError(f"{path}: the extension {suffix or '(none)'!r} does not say the "
                         "format; name the file .csv (long-format CSV) or .trace "
                         "(samples2LTL / Scarlet), or pass --format csv / --format trace")
    return FORMATS[suffix]


def input_format(path, fmt="auto", event_log=None):
    """How ``path`` is read: ``"csv"``, ``"trace"`` or ``"event-log"``.

    Parameters
    ----------
    path : str
    fmt : {"auto", "csv", "trace", "event-log"}, default="auto"
        ``auto`` decides by the extension; a ``.csv`` is an event log when ``event_log`` is
        given and the header has its case id column.
    event_log : dict, default=None
        The event-log options (``case_id``); ``None``: event logs are not accepted.
    """
    case_id = None if event_log is None else event_log.get("case_id") or EVENT_LOG_CASE_ID
    return _format_of(path, fmt, case_id)


def _has_column(path, column):
    """Whether the CSV file's header line names ``column``."""
    import csv

    try:
        with open(path, newline="", encoding="utf-8") as fh:
            header = next(csv.reader(fh), [])
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read ({exc})") from None
    return column in header


def load_demonstrations(path, fmt="auto", event_log=None):
    """Read one input file.

    Parameters
    ----------
    path : str
    fmt : {"auto", "csv", "trace", "event-log"}, default="auto"
        ``auto`` decides by the extension (``.csv`` or ``.trace``; with ``event_log``,
        ``.xes``, ``.xes.gz`` and a ``.csv`` with the case id column are event logs).
    event_log : dict, default=None
        Keyword arguments of :func:`bsi_sklearn.io.read_event_log` (``label``, ``pos_label``,
        ``labels``, ``case_id``, ``activity``, ``timestamp``) and ``encoder``, those of
        :class:`bsi_sklearn.io.EventLogEncoder` that encodes the log (default: its
        defaults); ``None``: no event logs.

    Returns
    -------
    X : list of DataFrame
    y : ndarray or None
        Labels (``None`` for a CSV file without a ``label`` column).
    target : LTL formula or None
        The target formula of a ``.trace`` file, when it has one.
    ids : list
        The demonstrations' ids: the CSV's ``demo_id`` values, the position (from 0) in a
        ``.trace`` file (positives, then negatives), or an event log's case ids.
    """
    from bsi_sklearn import io

    check_input(path)
    fmt = input_format(path, fmt, event_log)
    if fmt == "event-log":
        if event_log is None:
            raise ValueError(f"{path}: event logs are not read here (use bsi fit)")
        reader = dict(event_log)
        encoder = reader.pop("encoder", None) or {}
        cases, y, ids = io.read_event_log(path, **reader)
        X = io.EventLogEncoder(**encoder).fit_transform(cases)
        return X, y, None, list(ids)
    if fmt == "csv":
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
