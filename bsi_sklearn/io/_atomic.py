"""Write a file in one step: to a temporary name beside it, then renamed over it.

A writer interrupted half-way (an exception, a killed process) leaves no partial file at the
destination, only, at worst, a hidden temporary file. The file gets the mode a plain ``open``
would give it: the umask's for a new file, the old file's when it replaces one.
"""

from __future__ import annotations

import os
import secrets
import stat
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
    fd, tmp = _create_beside(path)
    try:
        with os.fdopen(fd, "wb") as fh:
            if path.is_file():  # keep the mode of the file it replaces, as open() would
                os.chmod(fh.fileno(), stat.S_IMODE(path.stat().st_mode))
            fh.write(raw)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def _create_beside(path):
    """Open a new hidden file beside ``path``: mode 0o666 less the umask, as ``open`` does."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):
        tmp = path.parent / f".{path.name}.{secrets.token_hex(6)}.tmp"
        try:
            return os.open(tmp, flags, 0o666), str(tmp)
        except FileExistsError:
            continue
    raise FileExistsError(f"no free temporary name beside {str(path)!r}")
