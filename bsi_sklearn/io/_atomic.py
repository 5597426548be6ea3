"""Write a file in one step: to a temporary name beside it, then renamed over it.

A writer interrupted half-way (an exception, a killed process) leaves no partial file at the
destination, only, at worst, a hidden temporary file.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

__all__ = ["write_atomic"]


def write_atomic(path, data, encoding="utf-8"):
    r"""Write ``data`` (str or bytes) to ``path`` through a temporary file and a rename.

    Parameters
    ----------
    path : str or path-like
        The destination; its folder must exist.
    data : str or bytes
        The content (str is encoded with ``encoding``).
    encoding : str, default="utf-8"

    Returns
    -------
    path : pathlib.Path

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     out = write_atomic(pathlib.Path(tmp) / "a.txt", "hello\n")
    ...     print(out.read_text(), end="")
    ...     print(sorted(p.name for p in pathlib.Path(tmp).iterdir()))
    hello
    ['a.txt']
    """
    path = Path(path)
    raw = data.encode(encoding) if isinstance(data, str) else bytes(data)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent or ".")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(raw)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path
