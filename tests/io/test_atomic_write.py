"""Writers leave no partial file: they write a temporary file and rename it."""

import numpy as np
import pytest

from bsi_sklearn.io import write_trace_file, write_traces_csv
from bsi_sklearn.io._atomic import write_atomic

X = [np.array([[1, 0], [1, 1]]), np.array([[0, 1]])]


@pytest.mark.parametrize("write", [
    lambda path: write_traces_csv(X, [1, 0], path),
    lambda path: write_trace_file(path, X, [1, 0]),
    lambda path: write_atomic(path, "text"),
])
def test_an_interrupted_write_leaves_nothing(tmp_path, monkeypatch, write):
    path = tmp_path / "out.txt"

    def fail(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr("os.replace", fail)
    with pytest.raises(OSError, match="disk full"):
        write(path)
    assert list(tmp_path.iterdir()) == []


def test_an_existing_file_is_replaced_whole(tmp_path):
    path = tmp_path / "out.csv"
    path.write_text("old content that is longer than the new one\n" * 10)
    write_traces_csv(X, [1, 0], path)
    assert path.read_text().startswith("demo_id,t,x0,x1,label\n")
    assert "old" not in path.read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_new_files_get_the_umask_mode_and_replaced_files_keep_theirs(tmp_path):
    import os

    old = os.umask(0o027)
    try:
        new = write_atomic(tmp_path / "new.txt", "x")
        kept = tmp_path / "kept.txt"
        kept.write_text("old")
        os.chmod(kept, 0o600)
        write_atomic(kept, "new")
    finally:
        os.umask(old)
    assert new.stat().st_mode & 0o777 == 0o640  # not mkstemp's 0o600
    assert kept.stat().st_mode & 0o777 == 0o600 and kept.read_text() == "new"
