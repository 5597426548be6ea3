"""Long-format traces: demo_id, t, prop...[, label] in pandas and CSV."""

import gzip
import io
import re

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn.io import read_traces_csv, traces_from_frame, traces_to_frame, write_traces_csv


def random_traces(seed=0, n=8, names=("a", "b", "c")):
    rng = np.random.default_rng(seed)
    return [pd.DataFrame(rng.random((int(rng.integers(1, 7)), len(names))) < 0.5,
                         columns=list(names)) for _ in range(n)]


def assert_same(got, expected):
    assert len(got) == len(expected)
    for g, e in zip(got, expected):
        assert list(g.columns) == list(e.columns)
        np.testing.assert_array_equal(g.to_numpy(), e.to_numpy())


def test_frame_round_trip_with_and_without_labels():
    X = random_traces()
    y = np.array([1, 0, 1, 1, 0, 0, 1, 0])
    frame = traces_to_frame(X, y)
    assert list(frame.columns) == ["demo_id", "t", "a", "b", "c", "label"]
    assert len(frame) == sum(len(x) for x in X)
    X2, y2 = traces_from_frame(frame)
    assert_same(X2, X)
    np.testing.assert_array_equal(y2, y)
    X3, y3 = traces_from_frame(traces_to_frame(X))
    assert_same(X3, X)
    assert y3 is None


def test_csv_round_trip_file_and_buffer(tmp_path):
    X = random_traces(1)
    y = np.arange(8) % 2
    path = tmp_path / "traces.csv"
    assert write_traces_csv(X, y, path) is None
    X2, y2 = read_traces_csv(path)
    assert_same(X2, X)
    np.testing.assert_array_equal(y2, y)
    text = write_traces_csv(X, None)
    X3, y3 = read_traces_csv(io.StringIO(text))
    assert_same(X3, X)
    assert y3 is None


def test_unnamed_arrays_get_x_names_and_custom_columns():
    X = np.array([[[1, 0], [0, 1]], [[1, 1], [0, 0]]])
    frame = traces_to_frame(X, ["ok", "bad"], demo_col="run", time_col="step",
                            label_col="verdict")
    assert list(frame.columns) == ["run", "step", "x0", "x1", "verdict"]
    X2, y2 = traces_from_frame(frame, demo_col="run", time_col="step", label_col="verdict")
    np.testing.assert_array_equal(np.stack([x.to_numpy() for x in X2]), X.astype(bool))
    assert y2.tolist() == ["ok", "bad"]
    frame = traces_to_frame(X, feature_names=["p", "q"])
    assert list(frame.columns) == ["demo_id", "t", "p", "q"]


def test_reader_sorts_time_and_keeps_demo_order():
    csv = "demo_id,t,a,b\nz,1,0,1\nz,0,1,0\nb,5,1,1\nb,6,0,0\n"
    X, y = read_traces_csv(io.StringIO(csv))
    assert y is None
    np.testing.assert_array_equal(X[0].to_numpy(), [[True, False], [False, True]])
    np.testing.assert_array_equal(X[1].to_numpy(), [[True, True], [False, False]])
    X, _ = read_traces_csv(io.StringIO("demo_id;t;a\n0;0;True\n0;1;False\n"), sep=";")
    assert X[0]["a"].tolist() == [True, False]


@pytest.mark.parametrize("csv, message", [
    ("demo_id,t,a\n0,0,1\n0,1,2\n", r"line 3: demonstration 0, step 1, "
     r"proposition 'a' has value 2"),
    ("demo_id,t,a\n0,0,1\n0,1,x\n", r"line 3: demonstration 0, step 1, "
     r"proposition 'a' has value 'x'"),
    ("demo_id,t,a\n0,0,1\n0,1,\n", r"line 3: demonstration 0, step 1, "
     r"proposition 'a' is missing \(the field is empty or NA"),
    ("demo_id,t,a\n0,0,1\n0,0,1\n", r"line 3: demonstration 0 has time step 0 twice"),
    ("demo_id,t,a\n0,0,1\n0,2,1\n", r"line 3: demonstration 0 jumps from time 0 to 2"),
    ("demo_id,t,a\n0,0,1\n0,0.5,1\n", r"line 3: time 0.5 is not an integer"),
    ("demo_id,t,a,label\n0,0,1,1\n0,1,1,0\n", r"line 3: the label of demonstration 0"),
    ("demo_id,t,a,label\n0,0,1,\n", r"line 2: the label of demonstration 0 is missing"),
    ("a,t\n0,1\n", r"no 'demo_id' column"),
    ("demo_id,t\n0,0\n", r"no proposition columns"),
    ("demo_id,t,a\n", r"no rows"),
    ("demo_id,t,a\n,0,1\n", r"line 2: missing 'demo_id'"),
    ("", r"No columns to parse"),
])
def test_csv_errors_name_the_line(csv, message):
    buf = io.StringIO(csv)
    buf.name = "bad.csv"
    with pytest.raises(ValueError, match=rf"bad\.csv.*{message}"):
        read_traces_csv(buf)


@pytest.mark.parametrize("csv, message", [
    # fewer fields: pandas would fill NaN, reported as a bad value 'nan'
    ("demo_id,t,a,b,label\n0,0,1,0,1\n0,1,1\n0,2,1,1,1\n",
     "bad.csv, line 3: the row has 3 fields, the header has 5 (demo_id, t, a, b, label)"),
    ("demo_id,t,a,b\n0,0,1,0\n\n0,1,1\n",  # a blank line is skipped, and counted
     "bad.csv, line 4: the row has 3 fields, the header has 4"),
    ("demo_id,t,a,label\n0,0,1,1\n0,1,1\n",  # only the label is lost
     "bad.csv, line 3: the row has 3 fields, the header has 4"),
    # more fields in one row: pandas' tokenizer error, worded the same way
    ("demo_id,t,a,label\n0,0,1,1\n0,1,1,0,1\n",
     "bad.csv, line 3: the row has 5 fields, the header has 4"),
    # one more in every row: pandas would take the first column as the index, silently
    ("demo_id,t,a,label\n0,0,1,0,1\n0,1,1,0,1\n",
     "bad.csv, line 2: the row has 5 fields, the header has 4"),
])
def test_ragged_rows_are_reported_by_line_not_as_a_bad_value(csv, message, tmp_path):
    buf = io.StringIO(csv)
    buf.name = "bad.csv"
    with pytest.raises(ValueError, match=re.escape(message)):
        read_traces_csv(buf)
    path = tmp_path / "bad.csv"
    path.write_text(csv)
    with pytest.raises(ValueError) as exc:
        read_traces_csv(path)
    assert str(exc.value).startswith(message.replace("bad.csv", str(path)))
    assert "nan" not in str(exc.value)
    gz = tmp_path / "bad.csv.gz"
    gz.write_bytes(gzip.compress(csv.encode()))
    with pytest.raises(ValueError, match=re.escape(message.replace("bad.csv", str(gz)))):
        read_traces_csv(gz)


def test_empty_fields_stay_missing_values():
    # a row with every field, one of them empty, is a missing value, not a ragged row
    buf = io.StringIO("demo_id,t,a,b\n0,0,1,0\n0,1,1,\n")
    buf.name = "gap.csv"
    with pytest.raises(ValueError, match=r"gap\.csv, line 3: demonstration 0, step 1, "
                                         r"proposition 'b' is missing \(the field is empty "
                                         r"or NA, or the row has fewer fields than the "
                                         r"header\); values must be 0 or 1") as exc:
        read_traces_csv(buf)
    assert "nan" not in str(exc.value)


@pytest.mark.parametrize("csv, kwargs", [
    ("demo_id,t,a,b\n0,0,1,0\n0,1,1\n", {"comment": "#"}),
    ("demo_id,t,a,b\n0,0,1,0\n0,1,1, NA\n", {"skipinitialspace": True}),
])
def test_missing_values_are_named_as_such_whatever_pandas_options(csv, kwargs):
    # with pandas options under which the fields are not counted (comment, ...), a short
    # row still reaches the values as NaN: it is reported as a missing field, not "value nan"
    buf = io.StringIO(csv)
    buf.name = "gap.csv"
    with pytest.raises(ValueError, match=r"gap\.csv, line 3: demonstration 0, step 1, "
                                         r"proposition 'b' is missing \(the field is empty "
                                         r"or NA, or the row has fewer fields") as exc:
        read_traces_csv(buf, **kwargs)
    assert "nan" not in str(exc.value)


def test_missing_values_of_a_frame_are_named_as_such():
    for missing in (np.nan, None, pd.NA):
        df = pd.DataFrame({"demo_id": [0, 0], "t": [0, 1], "a": [1, missing]}, index=[10, 11])
        with pytest.raises(ValueError, match=r"frame, row 11: demonstration 0, step 1, "
                                             r"proposition 'a' is missing "
                                             r"\((nan|None|<NA>)\); values"):
            traces_from_frame(df)


def test_frame_errors_name_the_row():
    df = pd.DataFrame({"demo_id": [0, 0], "t": [0, 1], "a": [1, 3]}, index=[10, 11])
    with pytest.raises(ValueError, match=r"frame, row 11: demonstration 0, step 1, "
                                         r"proposition 'a' has value 3"):
        traces_from_frame(df)
    with pytest.raises(ValueError, match="expected a pandas DataFrame"):
        traces_from_frame(df.to_numpy())


def test_writer_errors():
    X = [np.ones((2, 1))]
    with pytest.raises(ValueError, match="one label per demonstration"):
        traces_to_frame(X, [1, 0])
    with pytest.raises(ValueError, match="clash"):
        traces_to_frame([pd.DataFrame({"t": [1]})])
    with pytest.raises(ValueError, match="feature_names has 2 names"):
        traces_to_frame(X, feature_names=["a", "b"])
    with pytest.raises(ValueError, match="pass the destination as path_or_buffer"):
        write_traces_csv(X, "out.csv")
    with pytest.raises(ValueError, match="demonstration 0, step 0, proposition 0 has value 2"):
        traces_to_frame([np.full((1, 1), 2)])


def test_the_time_column_is_optional_as_in_the_python_api():
    # Issue 21: check_traces takes a long frame without 't'; the CSV reader required it.
    text = "demo_id,a,b,label\nrun1,1,0,1\nrun1,0,1,1\nrun0,1,1,0\n"
    X, y, ids = read_traces_csv(io.StringIO(text), return_ids=True)
    assert [x.to_numpy().tolist() for x in X] == [[[True, False], [False, True]],
                                                  [[True, True]]]
    assert y.tolist() == [1, 0] and ids.tolist() == ["run1", "run0"]
    assert list(X[0].columns) == ["a", "b"]


def test_ids_follow_the_demonstrations():
    X, y, ids = read_traces_csv(io.StringIO("demo_id,t,a\n7,0,1\n3,0,0\n7,1,1\n"),
                                return_ids=True)
    assert ids.tolist() == [7, 3] and [len(x) for x in X] == [2, 1] and y is None


@pytest.mark.parametrize("csv, column", [
    ("demo_id,t,time,a\n0,0,0.5,1\n0,1,1.0,0\n", "time"),
    ("demo_id,t,stamp,a\n0,0,1700000000,1\n0,1,1700000001,0\n", "stamp"),
])
def test_a_time_column_is_named_as_such_not_sent_to_binarize(csv, column):
    # Issue 21: a timestamp column got the advice to binarize it.
    with pytest.raises(ValueError, match=rf"proposition '{column}' has value .*the column looks "
                                         r"like a time stamp"):
        read_traces_csv(io.StringIO(csv))


def test_other_numeric_columns_keep_their_message():
    with pytest.raises(ValueError, match=r"has value 3\.0; values must be 0 or 1$"):
        read_traces_csv(io.StringIO("demo_id,t,speed\n0,0,3.0\n0,1,1.0\n"))
