"""Property-based fuzzing of the input readers: every failure is a ValueError naming where.

``check_traces``, the ``.trace`` and CSV readers and ``bsi fit`` get random malformed input;
each either succeeds or raises a ``ValueError`` (exit status 2 at the command line) whose
message names the demonstration, the line or the file. No other exception, no hang. Sizes and
example counts are small so that the whole file runs in seconds.
"""

import io
import re

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bsi_sklearn.cli import main
from bsi_sklearn.data.traces import Traces, check_traces
from bsi_sklearn.io import read_trace_file, read_traces_csv

FAST = settings(max_examples=60, deadline=2000, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow])

VALUES = st.sampled_from([0, 1, 1, 0, True, 2, -1, 0.5, np.nan, np.inf, "a", "1", None])
NAMES = st.sampled_from(["a", "b", "safe", "demo_id", "t", 0, 1])


@st.composite
def one_item(draw):
    """One demonstration, often malformed: array of any rank, nested lists, DataFrame."""
    kind = draw(st.sampled_from(["array", "nested", "frame", "scalar", "1d"]))
    if kind == "scalar":
        return draw(VALUES)
    if kind == "1d":
        return np.array(draw(st.lists(st.sampled_from([0, 1]), min_size=0, max_size=4)))
    rows = draw(st.integers(0, 3))
    cols = draw(st.integers(0, 3))
    if kind == "nested":
        return [draw(st.lists(VALUES, min_size=max(cols - 1, 0), max_size=cols + 1))
                for _ in range(rows)]
    values = [[draw(VALUES) for _ in range(cols)] for _ in range(rows)]
    if kind == "frame":
        names = draw(st.lists(NAMES, min_size=cols, max_size=cols))
        return pd.DataFrame(values, columns=names if cols else None)
    return np.array(values, dtype=object if draw(st.booleans()) else None) if all(
        isinstance(v, (int, float, bool)) for row in values for v in row) else values


@FAST
@given(st.lists(one_item(), min_size=0, max_size=4), st.sampled_from([None, 0.5]))
def test_check_traces_succeeds_or_names_the_demonstration(X, binarize):
    try:
        traces = check_traces(X, binarize=binarize)
    except ValueError as exc:
        message = str(exc)
        assert message
        # A problem with one item names it; otherwise the message is about the whole list.
        assert re.search(r"demonstration \d+|row \d+|at least one demonstration|"
                         r"demonstrations have no propositions", message), message
        return
    assert isinstance(traces, Traces)
    assert set(np.unique(traces.data).tolist()) <= {0, 1}
    assert traces.n_demos == len(X) and (traces.lengths >= 1).all()


@FAST
@given(st.one_of(one_item(), st.builds(np.zeros, st.tuples(st.integers(0, 2), st.integers(0, 2),
                                                           st.integers(0, 2), st.integers(1, 2)))))
def test_check_traces_on_a_single_object(X):
    try:
        check_traces(X)
    except ValueError as exc:
        assert str(exc)




@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory):
    """One folder for the files written by the examples (module scope: hypothesis reuses it)."""
    return tmp_path_factory.mktemp("fuzz")


VALID_TRACE = "1,0;1,1\n0,1\n---\n0,0;1,0\n---\nG,F,!\n---\n1\n---\nG(x0)\n"
VALID_CSV = "demo_id,t,a,b,label\n0,0,1,0,1\n0,1,1,1,1\n1,0,0,1,0\n1,1,0,0,0\n"


@st.composite
def mutated(draw, text, alphabet):
    """A valid file with up to three random edits: a character replaced, deleted or inserted,
    or a whole line dropped or repeated."""
    for _ in range(draw(st.integers(0, 3))):
        lines = text.split("\n")
        edit = draw(st.sampled_from(["replace", "delete", "insert", "drop", "repeat"]))
        if edit in ("drop", "repeat"):
            k = draw(st.integers(0, len(lines) - 1))
            lines[k:k + 1] = [] if edit == "drop" else [lines[k], lines[k]]
            text = "\n".join(lines)
            continue
        k = draw(st.integers(0, max(len(text) - 1, 0)))
        char = draw(st.sampled_from(alphabet))
        if edit == "replace":
            text = text[:k] + char + text[k + 1:]
        elif edit == "delete":
            text = text[:k] + text[k + 1:]
        else:
            text = text[:k] + char + text[k:]
    return text


TRACE_TEXT = st.one_of(mutated(VALID_TRACE, list("01,;-\n |x:2G")),
                       st.text(alphabet="01,;-\n |x:", max_size=40))
CSV_TEXT = st.one_of(mutated(VALID_CSV, list("01,\n x2.-\"t")),
                     st.text(alphabet="01,\nat_demoid", max_size=40))


@FAST
@given(TRACE_TEXT)
def test_trace_reader_names_file_and_line(fuzz_dir, text):
    path = fuzz_dir / "fuzz.trace"
    path.write_text(text, encoding="utf-8")
    try:
        tf = read_trace_file(path, formulas=None)
    except ValueError as exc:
        assert re.match(rf"{re.escape(str(path))}(, line \d+)?: ", str(exc)), str(exc)
        return
    assert all(t.ndim == 2 and len(t) >= 1 for t in tf.positives + tf.negatives)


@FAST
@given(CSV_TEXT)
def test_csv_reader_names_the_file(text):
    buf = io.StringIO(text)
    buf.name = "fuzz.csv"
    try:
        X, y = read_traces_csv(buf)
    except ValueError as exc:
        assert str(exc).startswith("fuzz.csv"), str(exc)
        return
    assert len(X) >= 1 and all(len(x) >= 1 for x in X)


@settings(max_examples=15, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(CSV_TEXT.map(lambda t: ("csv", t)), TRACE_TEXT.map(lambda t: ("trace", t))))
def test_bsi_fit_exits_2_naming_the_file(fuzz_dir, case):
    suffix, text = case
    path = fuzz_dir / f"cli.{suffix}"
    path.write_text(text, encoding="utf-8")
    err = io.StringIO()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr("sys.stderr", err)
        mp.setattr("sys.stdout", io.StringIO())
        status = main(["fit", str(path), "--n-samples", "20", "--inference", "exact"])
    if status == 2:
        message = err.getvalue()
        assert message.startswith("bsi fit: error: ") and str(path) in message, message
    else:
        assert status == 0
