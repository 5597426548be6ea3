"""``pandas.read_csv`` for the readers, with rows of the wrong width reported by line.

pandas accepts a row with fewer fields than the header and fills the rest with NaN (which the
readers would then report as a bad value ``nan``), and reads a file whose every row has one
field more than the header with the first column as the index (every column shifted, no
error). A ragged file is a broken file, so :func:`read_csv_rows` names its first ragged line.
"""

from __future__ import annotations

import bz2
import csv
import gzip
import io
import lzma
import os
import re

import pandas as pd

__all__ = ["read_csv_rows"]

# Options that leave one CSV record per line as the csv module reads it: with any other
# (skiprows, comment, names, ...) the fields are not counted and pandas' reading stands.
_COUNTABLE = {"sep", "delimiter", "encoding", "dtype"}
_OPENERS = {".gz": gzip.open, ".bz2": bz2.open, ".xz": lzma.open}
_TOO_MANY = re.compile(r"Expected (\d+) fields in line (\d+), saw (\d+)")


def read_csv_rows(source, name, **read_csv_kwargs):
    r"""Read a CSV file whose rows all have as many fields as its header.

    Parameters
    ----------
    source : str, path-like or file-like
        Anything :func:`pandas.read_csv` reads.
    name : str
        The file's name in messages.
    **read_csv_kwargs
        Passed to :func:`pandas.read_csv`.

    Returns
    -------
    frame : DataFrame

    Raises
    ------
    ValueError
        ``"<name>, line N: the row has M fields, the header has K"`` for the first row with
        fewer or more fields than the header. Other parser errors propagate as pandas raises
        them.

    Examples
    --------
    >>> import io
    >>> read_csv_rows(io.StringIO("a,b,c\n1,0,1\n1,0\n"), "demos.csv")
    Traceback (most recent call last):
    ...
    ValueError: demos.csv, line 3: the row has 2 fields, the header has 3 (a, b, c)...
    """
    start = _tell(source)
    try:
        frame = pd.read_csv(source, **read_csv_kwargs)
    except pd.errors.ParserError as exc:
        found = _TOO_MANY.search(str(exc))
        if found is None:
            raise
        k, line, m = found.groups()
        raise ValueError(f"{name}, line {line}: the row has {_fields(m)}, the header has {k}; "
                         "every row needs one value per column") from None
    # NaN (a short row fills the rest) or an inferred index (every row one field too many)
    # may come from ragged rows: only then are the fields counted.
    inferred_index = ("index_col" not in read_csv_kwargs
                      and not isinstance(frame.index, pd.RangeIndex))
    if inferred_index or frame.isna().to_numpy().any():
        ragged = _first_ragged_row(source, start, read_csv_kwargs)
        if ragged is not None:
            line, m, header = ragged
            raise ValueError(f"{name}, line {line}: the row has {_fields(m)}, the header has "
                             f"{len(header)} ({', '.join(header)}); every row needs one "
                             "value per column")
    return frame


def _fields(n):
    """``"1 field"``, ``"3 fields"``."""
    return f"{n} field{'' if int(n) == 1 else 's'}"


def _tell(source):
    """Where a seekable buffer starts (``None`` for a path or an unseekable stream)."""
    if isinstance(source, (str, os.PathLike)):
        return None
    try:
        return source.tell() if source.seekable() else None
    except (AttributeError, OSError, ValueError):
        return None


def _text(source, start, encoding):
    """The file's text, or ``None`` when it cannot be read again."""
    try:
        if isinstance(source, (str, os.PathLike)):
            path = os.fspath(source)
            suffix = os.path.splitext(path)[1].lower()
            if suffix in (".zip", ".zst", ".tar"):
                return None
            opener = _OPENERS.get(suffix, open)
            with opener(path, "rt", encoding=encoding, errors="replace", newline="") as fh:
                return fh.read()
        if start is None:
            return None
        source.seek(start)
        text = source.read()
    except (OSError, ValueError, EOFError, lzma.LZMAError):
        return None
    return text.decode(encoding, errors="replace") if isinstance(text, bytes) else text


def _first_ragged_row(source, start, kwargs):
    """``(line, n_fields, header)`` of the first row wider or narrower than the header."""
    if set(kwargs) - _COUNTABLE:
        return None
    sep = kwargs.get("sep", kwargs.get("delimiter", ","))
    if not isinstance(sep, str) or len(sep) != 1:
        return None
    text = _text(source, start, kwargs.get("encoding") or "utf-8")
    if text is None:
        return None
    reader = csv.reader(io.StringIO(text, newline=""), delimiter=sep)
    header = None
    for row in reader:
        if not row:  # a blank line, which pandas skips
            continue
        if header is None:
            header = row
        elif len(row) != len(header):
            return reader.line_num, len(row), header
    return None
