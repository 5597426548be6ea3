"""Write files in one step: to a temporary name beside each, then renamed over it.

A writer that fails half-way (a read-only folder, a full disk, a file-size limit, an
exception, a killed process) leaves no partial file at the destination and the previous file,
if any, unchanged; its temporary file is removed (only a killed process can leave one, hidden:
``.<name>.<random>.tmp``). Every failure is an ``OSError`` whose ``filename`` is the
destination, never the temporary name, so that the message names the file the user asked for.

A new file gets the mode a plain ``open`` would give it (the umask's); a replaced file keeps
its mode.

Every step goes through a function of :mod:`os` (``open``, ``fchmod``, ``write``, ``fsync``,
``close``, ``replace``), so that tests can make any of them fail.
"""

from __future__ import annotations

import os
import secrets
import stat
from pathlib import Path

__all__ = ["write_atomic", "write_files_atomic"]


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

    Raises
    ------
    OSError
        When any step fails, with ``filename`` the destination; the previous file is unchanged
        and no temporary file is left.

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
    return write_files_atomic({path: data}, encoding)[0]


def write_files_atomic(files, encoding="utf-8"):
    r"""Write several files, all or none: every one is written in full before any is renamed.

    When writing any of them fails, none of the destinations changes and every temporary file
    is removed. Only a failure of the final renames (rare: the temporary files already exist
    in the destinations' folders) can leave the earlier files new and the later ones old.

    Parameters
    ----------
    files : dict or iterable of (path, data) pairs
        Destination -> content (str or bytes); the folders must exist.
    encoding : str, default="utf-8"

    Returns
    -------
    paths : list of pathlib.Path
        The destinations, in order.

    Raises
    ------
    OSError
        Naming (``filename``) the destination whose step failed.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     d = pathlib.Path(tmp)
    ...     paths = write_files_atomic({d / "a.csv": "x\n1\n", d / "b.png": b"\x89PNG"})
    ...     print(sorted(p.name for p in d.iterdir()))
    ['a.csv', 'b.png']
    """
    items = list(files.items() if hasattr(files, "items") else files)
    staged = []
    try:
        for path, data in items:
            path = Path(path)
            raw = data.encode(encoding) if isinstance(data, str) else bytes(data)
            staged.append((_stage(path, raw), path))
    except BaseException:
        for tmp, _ in staged:
            _remove(tmp)
        raise
    for k, (tmp, path) in enumerate(staged):
        try:
            os.replace(tmp, path)
        except OSError as exc:
            for left, _ in staged[k:]:
                _remove(left)
            raise _naming(exc, path) from exc
        except BaseException:
            for left, _ in staged[k:]:
                _remove(left)
            raise
    return [path for _, path in staged]


def _stage(path, raw):
    """Write ``raw`` to a new temporary file beside ``path``, flushed to disk; its name."""
    fd, tmp = _create_beside(path)
    try:
        try:
            _keep_mode(fd, tmp, path)
            view = memoryview(raw)
            while view:
                view = view[os.write(fd, view):]
            os.fsync(fd)
        finally:
            os.close(fd)
    except OSError as exc:
        _remove(tmp)
        raise _naming(exc, path) from exc
    except BaseException:
        _remove(tmp)
        raise
    return tmp


def _keep_mode(fd, tmp, path):
    """Give the temporary file the mode of the file it replaces, as ``open`` would keep it."""
    try:
        st = os.stat(path)
    except OSError:  # no file there yet (or none we can see): the umask's mode stays
        return
    if not stat.S_ISREG(st.st_mode):
        return
    mode = stat.S_IMODE(st.st_mode)
    if hasattr(os, "fchmod"):
        os.fchmod(fd, mode)
    else:  # pragma: no cover - Windows before 3.13
        os.chmod(tmp, mode)


def _create_beside(path):
    """Open a new hidden file beside ``path``: mode 0o666 less the umask, as ``open`` does."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):
        tmp = path.parent / f".{path.name}.{secrets.token_hex(6)}.tmp"
        try:
            return os.open(tmp, flags, 0o666), str(tmp)
        except FileExistsError:
            continue
        except OSError as exc:
            raise _naming(exc, path) from exc
    raise FileExistsError(f"no free temporary name beside {str(path)!r}")


def _remove(tmp):
    try:
        os.unlink(tmp)
    except OSError:  # already gone, or the folder became unwritable: nothing more to do
        pass


def _naming(exc, path):
    """The ``OSError`` ``exc`` as one naming ``path`` (its subclass kept: PermissionError...)."""
    if exc.errno is None:  # OSError("text"): the text is the reason, after the file's name
        return OSError(f"{path}: {exc}")
    return OSError(exc.errno, exc.strerror or os.strerror(exc.errno), str(path))
