"""Where numba caches this package's compiled functions, also from a read-only installation.

numba caches a compiled function beside its module (``__pycache__``) or in the user's cache
folder, and raises ``RuntimeError: cannot cache function ...: no locator available`` at import
when neither can be written (a read-only installation with a read-only home). Before any
compiled function of the package is defined, :func:`configure_numba_cache` checks that numba
can cache them; when it cannot, it points numba's cache (``numba.config.CACHE_DIR``, what
``NUMBA_CACHE_DIR`` sets) to a private folder in the temporary directory, or, when nothing is
writable, turns caching off for this package's functions only. Either way it says so once, in
a warning.
"""

from __future__ import annotations

import os
import stat
import tempfile
import warnings
from pathlib import Path

__all__ = ["configure_numba_cache"]

_PACKAGE = Path(__file__).resolve().parent


def _probe():  # pragma: no cover - never called, only located
    pass


def _locator_classes():
    """The locators numba tries, in its order (its environment override included)."""
    from numba.core import caching, config

    override = getattr(config, "CACHE_LOCATOR_CLASSES", None)
    if not override:  # CacheImpl since numba 0.61, _CacheImpl before
        impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl
        return impl._locator_classes
    return [cls for cls in _override_classes(caching, override) if cls is not None]


def _override_classes(caching, text):
    import importlib

    for path in (p.strip() for p in text.split(",")):
        if "." in path:
            module, name = path.rsplit(".", 1)
            yield getattr(importlib.import_module(module), name, None)
        else:
            yield getattr(caching, path, None)


def _folders():
    """One source file in every folder of the package (numba caches per folder)."""
    seen = {}
    for path in sorted(_PACKAGE.rglob("*.py")):
        if "__pycache__" not in path.parts:
            seen.setdefault(path.parent, path)
    return list(seen.values())


def _in_tree_writable():
    """Numba's default, without importing numba: ``__pycache__`` writable in every folder.

    Only when numba's environment does not choose otherwise (``NUMBA_CACHE_DIR``, its
    locator override), since then numba's own locators decide.
    """
    if os.environ.get("NUMBA_CACHE_DIR") or os.environ.get("NUMBA_CACHE_LOCATOR_CLASSES"):
        return False
    try:
        for path in _folders():
            cache = path.parent / "__pycache__"
            cache.mkdir(exist_ok=True)
            tempfile.TemporaryFile(dir=cache).close()
    except OSError:
        return False
    return True


def _cache_possible():
    """Whether numba finds a writable cache for a function in every folder of the package."""
    classes = _locator_classes()
    return all(any(cls.from_function(_probe, str(path)) is not None for cls in classes)
               for path in _folders())


def _private_temporary_folder():
    """A folder only this user can write in the temporary directory, or None."""
    try:
        base = Path(tempfile.gettempdir())
    except (FileNotFoundError, OSError):
        return None
    user = os.getuid() if hasattr(os, "getuid") else os.environ.get("USERNAME", "user")
    folder = base / f"bsi_sklearn-numba-cache-{user}"
    try:
        folder.mkdir(mode=0o700, exist_ok=True)
        info = folder.lstat()
        if not stat.S_ISDIR(info.st_mode):
            return None
        if hasattr(os, "getuid") and (info.st_uid != os.getuid()
                                      or info.st_mode & (stat.S_IWGRP | stat.S_IWOTH)):
            return None  # someone else's folder: never load compiled code from it
        tempfile.TemporaryFile(dir=folder).close()
    except OSError:
        return None
    return folder


def _disable_caching_of_this_package():
    """Compile this package's functions without a cache; other packages' are untouched."""
    from numba.core.dispatcher import Dispatcher

    original = Dispatcher.enable_caching
    if getattr(original, "_bsi_sklearn_skips", False):
        return

    def enable_caching(self):
        if getattr(self.py_func, "__module__", "").split(".")[0] == "bsi_sklearn":
            return None  # the dispatcher keeps its NullCache
        return original(self)

    enable_caching._bsi_sklearn_skips = True
    Dispatcher.enable_caching = enable_caching


def configure_numba_cache():
    """Make sure importing the package does not fail for want of a numba cache folder.

    Returns
    -------
    where : str
        ``"default"`` (numba caches where it always does), ``"temporary"`` (in a private
        folder of the temporary directory) or ``"none"`` (this package's functions are
        compiled again by every process).

    Warns
    -----
    UserWarning
        When the cache is not where numba puts it by default.
    """
    if _in_tree_writable() or _cache_possible():
        return "default"
    from numba.core import config

    folder = _private_temporary_folder()
    if folder is not None:
        previous = config.CACHE_DIR
        config.CACHE_DIR = str(folder)
        if _cache_possible():
            warnings.warn(
                "numba cannot write its cache beside bsi_sklearn or in the user's cache folder "
                f"(a read-only installation?); compiled functions are cached in {folder} "
                "instead. Set NUMBA_CACHE_DIR to choose the folder.",
                UserWarning, stacklevel=3)
            return "temporary"
        config.CACHE_DIR = previous
    _disable_caching_of_this_package()
    warnings.warn(
        "numba finds no writable folder for its cache (a read-only installation and no "
        "writable temporary directory?); bsi_sklearn's compiled functions are not cached, so "
        "every process compiles them again (several seconds). Set NUMBA_CACHE_DIR to a "
        "writable folder to cache them.",
        UserWarning, stacklevel=3)
    return "none"
