"""Faults of the file system, made on purpose: a read-only folder, a failing step of a write.

Tests run as root, so permission bits do not stop a write; these context managers make the
operating system's answers instead, by patching the functions every writer goes through.

- :func:`read_only`: every attempt to create, write, replace, rename or remove a file in a
  folder (or to make a folder in it) fails as on a read-only folder or file system, whatever
  the writer (``open``, pandas, matplotlib, ``pathlib``, ``os``); reading still works.
- :func:`full_after`: the first files made in a folder are written, the next ones cannot be
  made (a full disk, a quota): a writer of several files fails after writing some.
- :func:`failing_step`: the ``nth`` call of one step of an atomic write (``open`` of the
  temporary file, ``fchmod``, ``write``, ``fsync``, ``close``, ``replace``) fails with an
  errno, as a full disk or a file-size limit would; writes are short (a few bytes each) so
  that a failure can land half-way through a file.
- :func:`snapshot`: every file under a folder (hidden ones too) with its bytes.
"""

from __future__ import annotations

import builtins
import contextlib
import errno
import io
import os
from pathlib import Path
from unittest import mock

#: The failures a read-only target or a full disk gives.
ERRNOS = (errno.EACCES, errno.EROFS, errno.ENOSPC, errno.EFBIG)
#: The steps of an atomic write (``bsi_sklearn.io._atomic``), in order.
STEPS = ("open", "fchmod", "write", "fsync", "close", "replace")

_WRITE_FLAGS = os.O_WRONLY | os.O_RDWR | os.O_CREAT | os.O_TRUNC | os.O_APPEND


def _error(code, filename=None):
    return OSError(code, os.strerror(code), *(() if filename is None else (str(filename),)))


def _inside(path, folder):
    try:
        Path(os.path.abspath(os.fspath(path))).relative_to(folder)
    except (TypeError, ValueError):
        return False
    return True


@contextlib.contextmanager
def read_only(folder, code=errno.EACCES):
    """Within the block, ``folder`` (and everything under it) cannot be changed.

    Parameters
    ----------
    folder : path-like
    code : int, default=errno.EACCES
        The errno of every refusal (``EACCES``: no write permission; ``EROFS``: a read-only
        file system).

    Yields
    ------
    refused : list of str
        The paths refused, in order.
    """
    with _refusing(folder, code, allowed=0, deletions=False) as refused:
        yield refused


@contextlib.contextmanager
def full_after(folder, n_files, code=errno.ENOSPC):
    """Within the block, the first ``n_files`` files made under ``folder`` can be written,
    the next ones cannot be made (a full disk or quota); renames and deletions still work.

    Yields
    ------
    refused : list of str
        The paths refused, in order.
    """
    with _refusing(folder, code, allowed=n_files, deletions=True) as refused:
        yield refused


@contextlib.contextmanager
def _refusing(folder, code, allowed, deletions):
    folder = Path(os.path.abspath(folder))
    refused = []
    made = [0]
    real_open, real_os_open = builtins.open, os.open
    real = {name: getattr(os, name) for name in ("mkdir", "replace", "rename", "unlink",
                                                  "remove", "rmdir")}

    def check(path, creation=True):
        if not _inside(path, folder):
            return
        if creation == "folder" and deletions:  # a full disk: existing folders are reused
            return
        if creation is True and made[0] < allowed:
            made[0] += 1
            return
        if not creation and deletions:
            return
        refused.append(str(path))
        raise _error(code, path)

    def fake_open(file, mode="r", *args, **kwargs):
        if isinstance(file, (str, bytes, os.PathLike)) and any(c in mode for c in "wax+"):
            check(file)
        return real_open(file, mode, *args, **kwargs)

    def fake_os_open(path, flags, *args, **kwargs):
        if flags & _WRITE_FLAGS:
            check(path)
        return real_os_open(path, flags, *args, **kwargs)

    def guard(name, n_paths, creation):
        def fake(*args, **kwargs):
            for path in args[:n_paths]:
                check(path, creation)
            return real[name](*args, **kwargs)
        return fake

    with contextlib.ExitStack() as stack:
        stack.enter_context(mock.patch.object(builtins, "open", fake_open))
        stack.enter_context(mock.patch.object(io, "open", fake_open))
        stack.enter_context(mock.patch.object(os, "open", fake_os_open))
        for name, n_paths, creation in (("mkdir", 1, "folder"), ("replace", 2, False),
                                        ("rename", 2, False), ("unlink", 1, False),
                                        ("remove", 1, False), ("rmdir", 1, False)):
            stack.enter_context(mock.patch.object(os, name, guard(name, n_paths, creation)))
        yield refused


def _is_temporary(path):
    name = Path(os.fspath(path)).name
    return name.startswith(".") and name.endswith(".tmp")


@contextlib.contextmanager
def failing_step(step, code, nth=0, chunk=64):
    """Within the block, the ``nth`` call (from 0) of ``step`` of an atomic write fails.

    Only the calls on the writers' temporary files (``.<name>.<random>.tmp``) count and fail;
    every ``os.write`` on them writes at most ``chunk`` bytes. A failing ``close`` releases
    the descriptor first, as the system call does; a failing ``write`` writes half its bytes.

    Yields
    ------
    state : dict
        ``fired`` (whether the fault happened) and ``calls`` (calls of ``step`` counted).
    """
    assert step in STEPS, step
    state = {"fired": False, "calls": 0}
    fds = set()
    real = {name: getattr(os, name) for name in ("open", "fchmod", "write", "fsync", "close",
                                                  "replace")}

    def fire(filename=None):
        k = state["calls"]
        state["calls"] += 1
        if k == nth:
            state["fired"] = True
            raise _error(code, filename)

    def fake_open(path, flags, *args, **kwargs):
        if not _is_temporary(path):
            return real["open"](path, flags, *args, **kwargs)
        if step == "open":
            fire(path)  # as the system names it: the temporary file
        fd = real["open"](path, flags, *args, **kwargs)
        fds.add(fd)
        return fd

    def fake_write(fd, data):
        if fd not in fds:
            return real["write"](fd, data)
        data = memoryview(data)[:chunk]
        if step == "write":
            k = state["calls"]
            if k == nth:
                real["write"](fd, data[:max(1, len(data) // 2)])
            fire()
        return real["write"](fd, data)

    def fake_fd_step(name):
        def fake(fd, *args):
            ours = fd in fds
            if name == "close":
                fds.discard(fd)
            if ours and step == name:
                if name == "close":  # the descriptor is released whatever close answers
                    real["close"](fd)
                    fire()
                    return None
                fire()
            return real[name](fd, *args)
        return fake

    def fake_replace(src, dst, *args, **kwargs):
        if step == "replace" and _is_temporary(src):
            fire(src)
        return real["replace"](src, dst, *args, **kwargs)

    with contextlib.ExitStack() as stack:
        stack.enter_context(mock.patch.object(os, "open", fake_open))
        stack.enter_context(mock.patch.object(os, "write", fake_write))
        stack.enter_context(mock.patch.object(os, "replace", fake_replace))
        for name in ("fchmod", "fsync", "close"):
            stack.enter_context(mock.patch.object(os, name, fake_fd_step(name)))
        yield state


def snapshot(folder):
    """``{relative path: bytes}`` of every file under ``folder``, hidden files included."""
    folder = Path(folder)
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def temporaries(folder):
    """The writers' temporary files left under ``folder``."""
    return sorted(p.name for p in Path(folder).rglob("*") if _is_temporary(p))
