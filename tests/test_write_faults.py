"""Writers under read-only folders, full disks and failing steps (issue 21's fault suite).

Tests run as root, where permission bits stop nothing, so the faults are made by patching the
functions every writer goes through (``tests/_faults.py``). For every writer, the API raises
an ``OSError`` (or ``ValueError``) naming the destination, never the hidden temporary file,
and a command prints one line naming it and exits with status 2; in both cases the previous
output is left byte for byte and no temporary file stays behind.
"""

from __future__ import annotations

import contextlib
import errno
import io
import os

import numpy as np
import pandas as pd
import pytest
from _faults import ERRNOS, STEPS, failing_step, full_after, read_only, snapshot, temporaries
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bsi_sklearn import BSIClassifier, Posterior
from bsi_sklearn.cli import main as bsi
from bsi_sklearn.io import write_atomic, write_files_atomic, write_traces_csv

NAMES = ["safe", "picked", "placed"]
GOOD = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
        np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
BAD = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
ROLES = ["--globals", "safe", "--subtasks", "picked", "placed"]
FAULT_SETTINGS = settings(max_examples=60, deadline=None, derandomize=True,
                          suppress_health_check=[HealthCheck.function_scoped_fixture])


def _error_line(capsys):
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert "Traceback" not in err and len(lines) == 1, err
    assert ".tmp" not in err, err  # the destination is named, not the hidden temporary file
    return lines[0]


def _mark_previous(folder):
    """Give every file under ``folder`` a content no writer would write; the snapshot."""
    for path in sorted(folder.rglob("*")):
        if path.is_file():
            path.write_bytes(b"previous output of " + path.name.encode())
    return snapshot(folder)


def _check_os_error(exc, destinations):
    text = str(exc)
    assert ".tmp" not in text, text
    assert any(str(d) in text for d in destinations), text
    if exc.errno is not None:
        assert exc.filename in {str(d) for d in destinations}


# ------------------------------------------------------------------ write_atomic: every step
@FAULT_SETTINGS
@given(step=st.sampled_from(STEPS), code=st.sampled_from(ERRNOS), nth=st.integers(0, 12),
       n_files=st.integers(1, 4), existing=st.lists(st.booleans(), min_size=4, max_size=4),
       sizes=st.lists(st.integers(0, 300), min_size=4, max_size=4))
def test_write_files_atomic_all_or_none_whichever_step_fails(tmp_path_factory, step, code, nth,
                                                            n_files, existing, sizes):
    folder = tmp_path_factory.mktemp("atomic")
    paths = [folder / f"out{k}.bin" for k in range(n_files)]
    for path, there in zip(paths, existing):
        if there:
            path.write_bytes(b"old " + path.name.encode())
            os.chmod(path, 0o640)
    before = snapshot(folder)
    data = {p: bytes([k + 1]) * size for k, (p, size) in enumerate(zip(paths, sizes))}
    with failing_step(step, code, nth) as state:
        try:
            write_files_atomic(data)
        except OSError as exc:
            assert state["fired"]
            _check_os_error(exc, paths)
            assert exc.errno == code
            if step != "replace":  # a failed rename can leave the earlier files new
                assert snapshot(folder) == before
            else:
                now = snapshot(folder)
                assert all(now.get(p.name) in (before.get(p.name), data[p]) for p in paths)
        else:
            assert not state["fired"]
            assert snapshot(folder) == {p.name: d for p, d in data.items()}
            for path, there in zip(paths, existing):
                assert path.stat().st_mode & 0o777 == (0o640 if there else 0o666 & ~_umask())
    assert temporaries(folder) == []


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_a_full_disk_half_way_through_a_file_names_it(tmp_path):
    # Before: the OSError of a failed write named no file (and the temporary one for open).
    path = tmp_path / "out.csv"
    path.write_text("previous\n")
    with failing_step("write", errno.ENOSPC, nth=1), pytest.raises(OSError) as exc:
        write_atomic(path, "x" * 500)
    assert exc.value.filename == str(path) and exc.value.errno == errno.ENOSPC
    assert path.read_text() == "previous\n" and temporaries(tmp_path) == []


@pytest.mark.parametrize("code", [errno.EACCES, errno.EROFS])
def test_write_atomic_in_a_read_only_folder_names_the_file(tmp_path, code):
    path = tmp_path / "out.json"
    path.write_text("previous")
    with read_only(tmp_path, code), pytest.raises(OSError) as exc:
        write_atomic(path, "new")
    assert exc.value.errno == code and exc.value.filename == str(path)
    assert isinstance(exc.value, PermissionError) == (code == errno.EACCES)
    assert path.read_text() == "previous" and temporaries(tmp_path) == []


# ------------------------------------------------------------------ Posterior.to_json
@pytest.fixture(scope="module")
def fitted():
    X = [pd.DataFrame(x, columns=NAMES) for x in GOOD + BAD]
    y = np.array([1, 1, 0])
    clf = BSIClassifier(global_candidates=["safe"], subtasks=["picked", "placed"],
                        random_state=0).fit(X, y)
    return clf, X, y


@FAULT_SETTINGS
@given(step=st.sampled_from(STEPS), code=st.sampled_from(ERRNOS), nth=st.integers(0, 40),
       previous=st.booleans())
def test_to_json_whichever_step_fails(fitted, tmp_path_factory, step, code, nth, previous):
    folder = tmp_path_factory.mktemp("post")
    path = folder / "posterior.json"
    if previous:
        path.write_text("the previous posterior")
    before = snapshot(folder)
    with failing_step(step, code, nth) as state:
        try:
            fitted[0].posterior_.to_json(path)
        except OSError as exc:
            assert state["fired"]
            _check_os_error(exc, [path])
            assert snapshot(folder) == before
        else:
            assert not state["fired"]
            assert Posterior.read_json(path).roles.names == NAMES
    assert temporaries(folder) == []


@pytest.mark.parametrize("code", [errno.EACCES, errno.EROFS])
def test_to_json_into_a_read_only_folder(fitted, tmp_path, code):
    # Before: PermissionError: [Errno 13] ... '.posterior.json.3f2a....tmp' (the temporary name)
    path = tmp_path / "posterior.json"
    fitted[0].posterior_.to_json(path)
    before = snapshot(tmp_path)
    with read_only(tmp_path, code), pytest.raises(OSError) as exc:
        fitted[0].posterior_.to_json(path)
    _check_os_error(exc.value, [path])
    assert snapshot(tmp_path) == before


# ------------------------------------------------------------------ the report writers
@pytest.fixture(scope="module")
def report(fitted):
    from bsi_sklearn.report import explain

    clf, X, y = fitted
    return explain(clf, X, y, title="faults")


def test_report_to_markdown_is_all_or_none(report, tmp_path):
    # Before: the figures were written one by one, so a disk that filled up after two of them
    # left a new satisfaction.png beside the previous report.md.
    folder = tmp_path / "report"
    report.to_markdown(folder)
    before = _mark_previous(folder)
    n_files = len(before)
    assert n_files >= 3
    for k in range(n_files):
        with full_after(folder, k), pytest.raises(OSError) as exc:
            report.to_markdown(folder)
        _check_os_error(exc.value, [folder / name for name in before])
        assert snapshot(folder) == before, k
    assert temporaries(folder) == []
    report.to_markdown(folder)
    assert snapshot(folder) != before and temporaries(folder) == []


@pytest.mark.parametrize("code", [errno.EACCES, errno.EROFS])
def test_report_writers_in_a_read_only_folder(report, tmp_path, code):
    report.to_markdown(tmp_path)
    report.to_html(tmp_path / "report.html")
    before = _mark_previous(tmp_path)
    with read_only(tmp_path, code), pytest.raises(OSError) as exc:
        report.to_markdown(tmp_path)
    _check_os_error(exc.value, [tmp_path / name for name in before])
    with read_only(tmp_path, code), pytest.raises(OSError) as exc:
        report.to_html(tmp_path / "report.html")
    _check_os_error(exc.value, [tmp_path / "report.html"])
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("step, code", [("write", errno.ENOSPC), ("fsync", errno.EIO),
                                        ("replace", errno.EROFS)])
def test_report_to_html_failing_step(report, tmp_path, step, code):
    path = tmp_path / "report.html"
    path.write_text("previous")
    with failing_step(step, code) as state, pytest.raises(OSError) as exc:
        report.to_html(path)
    assert state["fired"]
    _check_os_error(exc.value, [path])
    assert path.read_text() == "previous" and temporaries(tmp_path) == []


# ------------------------------------------------------------------ bsi fit --save
@pytest.fixture
def demos(tmp_path):
    path = tmp_path / "in" / "demos.csv"
    path.parent.mkdir()
    write_traces_csv(GOOD + BAD, [1, 1, 0], path, feature_names=NAMES)
    return path


def _fault(kind, folder):
    """A context manager making the fault ``kind`` in ``folder``."""
    if kind in ("EACCES", "EROFS"):
        return read_only(folder, getattr(errno, kind))
    step, code = kind.split(":")
    return failing_step(step, getattr(errno, code))


FIT_FAULTS = ["EACCES", "EROFS", "open:EROFS", "write:ENOSPC", "write:EFBIG", "fsync:EIO",
              "close:ENOSPC", "replace:EACCES"]


@pytest.mark.parametrize("kind", FIT_FAULTS)
def test_fit_save_faults(demos, tmp_path, capsys, kind):
    folder = tmp_path / "out"
    folder.mkdir()
    out = folder / "post.json"
    out.write_text("the previous posterior")
    before = snapshot(folder)
    with _fault(kind, folder):
        status = bsi(["fit", str(demos), *ROLES, "--save", str(out)])
    assert status == 2
    line = _error_line(capsys)
    assert line.startswith(f"bsi fit: error: --save {out}: cannot write (")
    assert "the previous file, if any, is unchanged" in line
    assert snapshot(folder) == before


# ------------------------------------------------------------------ bsi monitor --out
@pytest.fixture
def saved(demos, tmp_path):
    out = tmp_path / "post.json"
    assert bsi(["fit", str(demos), *ROLES, "--save", str(out)]) == 0
    return out


@pytest.mark.parametrize("kind", ["EACCES", "EROFS", "full:1", "full:3", "write:ENOSPC",
                                  "replace:EROFS"])
def test_monitor_out_faults(saved, demos, tmp_path, capsys, kind):
    # Before: the tables and plots were written one demonstration at a time, so a disk that
    # filled up half-way left some new and some previous outputs.
    folder = tmp_path / "monitor"
    assert bsi(["monitor", str(saved), str(demos), "--out", str(folder)]) == 0
    before = _mark_previous(folder)
    assert len(before) == 6  # 3 demonstrations: a table and a plot each
    capsys.readouterr()
    fault = (full_after(folder, int(kind[5:])) if kind.startswith("full:")
             else _fault(kind, folder))
    with fault:
        status = bsi(["monitor", str(saved), str(demos), "--out", str(folder)])
    assert status == 2
    line = _error_line(capsys)
    assert line.startswith("bsi monitor: error: ") and str(folder) in line
    assert snapshot(folder) == before


def test_monitor_out_under_a_read_only_folder(saved, demos, tmp_path, capsys):
    parent = tmp_path / "ro"
    parent.mkdir()
    with read_only(parent):
        status = bsi(["monitor", str(saved), str(demos), "--out", str(parent / "new")])
    assert status == 2
    assert str(parent / "new") in _error_line(capsys)
    assert list(parent.iterdir()) == []


# ------------------------------------------------------------------ bsi-lfe
lfe_cli = pytest.importorskip("lfe.cli")


def _lfe(argv):
    with contextlib.redirect_stdout(io.StringIO()):
        return lfe_cli.main(argv)


@pytest.mark.parametrize("kind", ["EACCES", "EROFS", "full:0", "full:3", "full:6",
                                  "open:EACCES", "write:ENOSPC", "close:EIO"])
def test_lfe_simulate_out_faults(tmp_path, capsys, kind):
    # Before: LFEDataset.save wrote its seven files one by one, in place: a disk that filled
    # up after three left new tracks / weapons / sites beside the previous meta.json, and a
    # failure half-way through a file left it cut.
    folder = tmp_path / "data"
    argv = ["simulate", "--n-scenarios", "2", "--out", str(folder)]
    assert _lfe(argv) == 0
    before = _mark_previous(folder)
    assert len(before) == 7
    capsys.readouterr()
    fault = (full_after(folder, int(kind[5:])) if kind.startswith("full:")
             else _fault(kind, folder))
    with fault:
        status = _lfe(argv)
    assert status == 2
    line = _error_line(capsys)
    assert line.startswith("bsi-lfe simulate: error: ") and str(folder) in line
    assert snapshot(folder) == before


def test_lfe_simulate_out_under_a_read_only_folder(tmp_path, capsys):
    with read_only(tmp_path, errno.EROFS):
        status = _lfe(["simulate", "--n-scenarios", "2", "--out", str(tmp_path / "new")])
    assert status == 2
    assert str(tmp_path / "new") in _error_line(capsys)
    assert list(tmp_path.iterdir()) == []


@pytest.fixture(scope="module")
def comparison():
    pytest.importorskip("torch")
    from lfe.compare import compare
    from lfe.dataset import make_lfe_dataset

    return compare(make_lfe_dataset(4, random_state=1), quick=True, seed=0, verbose=0,
                   n_splits=2)


@pytest.mark.parametrize("kind", ["EACCES", "full:2", "full:5", "write:ENOSPC"])
def test_lfe_compare_out_faults(comparison, tmp_path, capsys, monkeypatch, kind):
    # Before: the six files (tables, LaTeX, figure) were written one by one, in place.
    import lfe.compare

    # The command line (lfe.cli._compare.run) imports `compare` from lfe.compare when it runs:
    # that name is the one to replace (the protocol module's own binding is not read, and
    # patching it ran the whole comparison twice per case).
    monkeypatch.setattr(lfe.compare, "compare", lambda *args, **kwargs: comparison)
    folder = tmp_path / "results"
    assert _lfe(["compare", "--out", str(folder), "--verbose", "0"]) == 0
    before = _mark_previous(folder)
    assert len(before) == 7  # the tables, LaTeX, figure, times, MAP F1 and probabilities
    capsys.readouterr()
    fault = (full_after(folder, int(kind[5:])) if kind.startswith("full:")
             else _fault(kind, folder))
    with fault:
        status = _lfe(["compare", "--out", str(folder), "--verbose", "0"])
    assert status == 2
    line = _error_line(capsys)
    assert line.startswith("bsi-lfe compare: error: ") and str(folder) in line
    assert snapshot(folder) == before


@pytest.mark.parametrize("kind", ["EROFS", "full:1", "full:4", "replace:EACCES"])
def test_lfe_report_out_faults(report, tmp_path, capsys, monkeypatch, kind):
    # Before: each objective's folder, then index.html, were written file by file.
    import lfe.report

    monkeypatch.setattr(lfe.report, "explain_objectives",
                        lambda *args, **kwargs: {"MO1": report, "MO2": report})
    monkeypatch.setattr(lfe.report, "load_lfe_dataset", lambda path: None)
    folder = tmp_path / "lfe_report"
    argv = ["report", "--out", str(folder)]
    assert _lfe(argv) == 0
    before = _mark_previous(folder)
    assert len(before) > 6
    capsys.readouterr()
    fault = (full_after(folder, int(kind[5:])) if kind.startswith("full:")
             else _fault(kind, folder))
    with fault:
        status = _lfe(argv)
    assert status == 2
    line = _error_line(capsys)
    assert line.startswith("bsi-lfe report: error: ") and str(folder) in line
    assert snapshot(folder) == before
