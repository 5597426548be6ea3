"""A read-only installation imports and fits (issue 21): numba's cache falls back to a private
temporary folder, or to no cache, with a warning, instead of failing at import.

The tests run as root here, where file modes do not stop writes, so a read-only file system is
simulated in a subprocess: numba's check that a cache folder is writable fails for every folder
but the allowed one.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

_READ_ONLY = """
import errno, sys, types
from numba.core import caching
allowed, bypass = sys.argv[1], sys.argv[2] == "bypass"
real = caching._CacheLocator.ensure_cache_path
def read_only(self):
    if allowed == "none" or not self.get_cache_path().startswith(allowed):
        raise OSError(errno.EROFS, "Read-only file system", self.get_cache_path())
    return real(self)
caching._CacheLocator.ensure_cache_path = read_only
if bypass:  # what the package did before: no check of the cache
    fake = types.ModuleType("bsi_sklearn._numba_cache")
    fake.configure_numba_cache = lambda: None
    sys.modules["bsi_sklearn._numba_cache"] = fake
import numpy as np
import bsi_sklearn
clf = bsi_sklearn.BSIClassifier(random_state=0).fit([np.array([[1, 0], [1, 1]])])
print("MAP", clf.map_specification_)
from numba.core import config
print("CACHE_DIR", config.CACHE_DIR)
"""


def _run(tmp_path, allowed, bypass=False):
    # numba's default locators, named: the package then asks numba itself (its quick check
    # of the package's own folders, done without numba, would see the real, writable disk).
    env = dict(os.environ, PYTHONPATH=str(ROOT), TMPDIR=str(tmp_path),
               NUMBA_CACHE_LOCATOR_CLASSES="UserProvidedCacheLocator,InTreeCacheLocator,"
                                           "UserWideCacheLocator")
    env.pop("NUMBA_CACHE_DIR", None)
    return subprocess.run([sys.executable, "-c", _READ_ONLY, allowed,
                           "bypass" if bypass else "check"], capture_output=True, text=True,
                          env=env, timeout=600, cwd=tmp_path)


def test_without_the_check_a_read_only_installation_fails_at_import(tmp_path):
    out = _run(tmp_path, "none", bypass=True)
    assert out.returncode != 0 and "no locator available" in out.stderr


@pytest.mark.slow
def test_read_only_installation_caches_in_a_private_temporary_folder(tmp_path):
    out = _run(tmp_path, str(tmp_path))
    assert out.returncode == 0, out.stderr
    folder = tmp_path / f"bsi_sklearn-numba-cache-{os.getuid()}"
    assert f"CACHE_DIR {folder}" in out.stdout and "MAP G(0)" in out.stdout
    assert f"compiled functions are cached in {folder}" in out.stderr
    assert folder.stat().st_mode & 0o077 == 0 and any(folder.iterdir())


@pytest.mark.slow
def test_nothing_writable_compiles_without_a_cache(tmp_path):
    out = _run(tmp_path, "none")
    assert out.returncode == 0, out.stderr
    assert "MAP G(0)" in out.stdout and "CACHE_DIR \n" in out.stdout
    assert "compiled functions are not cached" in out.stderr


def test_a_folder_of_another_user_is_never_used(tmp_path, monkeypatch):
    from bsi_sklearn import _numba_cache

    monkeypatch.setattr("tempfile.gettempdir", lambda: str(tmp_path))
    folder = tmp_path / f"bsi_sklearn-numba-cache-{os.getuid()}"
    folder.mkdir(mode=0o777)
    os.chmod(folder, 0o777)  # writable by others: someone could plant compiled code there
    assert _numba_cache._private_temporary_folder() is None
    os.chmod(folder, 0o700)
    assert _numba_cache._private_temporary_folder() == folder


def test_a_writable_installation_keeps_numba_defaults():
    from bsi_sklearn import _numba_cache

    assert _numba_cache.configure_numba_cache() == "default"
    assert _numba_cache._in_tree_writable() == (not os.environ.get("NUMBA_CACHE_DIR"))
