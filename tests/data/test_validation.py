import numpy as np
import pandas as pd
import pytest

from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_labels, check_traces
from bsi_sklearn.io import read_traces_csv, write_traces_csv


def test_formats_agree():
    rng = np.random.default_rng(0)
    arr3 = rng.integers(0, 2, size=(4, 3, 2))
    from_3d = check_traces(arr3)
    from_list = check_traces([a for a in arr3])
    from_frames = check_traces([pd.DataFrame(a, columns=["p", "q"]) for a in arr3])
    assert np.array_equal(from_3d.data, from_list.data)
    assert np.array_equal(from_3d.data, from_frames.data)
    assert list(from_frames.feature_names) == ["p", "q"]
    flat = check_traces(rng.integers(0, 2, size=(5, 3)))
    assert flat.n_demos == 5 and list(flat.lengths) == [1] * 5
    ragged = check_traces([np.ones((2, 2)), np.zeros((5, 2))])
    assert list(ragged.lengths) == [2, 5]


@pytest.mark.parametrize(
    "X, match",
    [
        ([], "at least one demonstration"),
        (np.zeros((0, 3)), "at least one demonstration"),
        ([np.ones((2, 2)), np.ones((0, 2))], "demonstration 1 has zero length"),
        ([np.ones((2, 2)), np.ones((2, 3))], "demonstration 1 has 3 propositions"),
        ([np.array([[0, 1], [np.nan, 1]])], "demonstration 0, step 1, proposition 0 is nan"),
        ([np.array([[0, 2]])], "demonstration 0, step 0, proposition 1 has value 2"),
        ([np.ones((2, 2)), np.ones(3)], r"demonstration 1 is a 1-D array .*reshape\(-1, 1\)"),
        ([np.ones((2, 2)), np.ones((2, 2, 1))], "demonstration 1 must be a 2-D"),
        (np.ones((2, 2, 2, 2)), "4 dimension"),
        ([np.array([["a", "b"]])], "demonstration 0, step 0, proposition 0 has the non-numeric"),
        ([[[0, 1], [1]]], "demonstration 0 is ragged: step 1 has 1 propositions, step 0 has 2"),
        ([[0, 1], [1]], r"list of lists \(scikit-learn's 2-D format, every row a demonstration "
                        r"of length one\) whose row 1 has 1 propositions, row 0 has 2"),
        (np.array([[0, 1], [3, 1]]), "demonstration 1, step 0, proposition 0 has value 3"),
        ("abc", "demonstrations must be"),
    ],
)
def test_bad_traces(X, match):
    with pytest.raises(ValueError, match=match):
        check_traces(X)


def test_frames_must_agree_and_binarize():
    a = pd.DataFrame([[1, 0]], columns=["p", "q"])
    b = pd.DataFrame([[1, 0]], columns=["q", "p"])
    with pytest.raises(ValueError, match="demonstration 1 has columns"):
        check_traces([a, b])
    t = check_traces([np.array([[0.2, 0.7]])], binarize=0.5)
    assert t.data.tolist() == [[0, 1]]
    with pytest.raises(ValueError, match="binarize"):
        check_traces([np.array([[0.2, 0.7]])], binarize="x")


def test_demonstrations_of_files_with_different_headers_name_the_column(tmp_path):
    # two CSV files of one data set, the second written without 'placed': fit must refuse
    names = ["safe", "picked", "placed"]
    good = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    bad = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
    write_traces_csv(good, [1], tmp_path / "a.csv", feature_names=names)
    write_traces_csv([b[:, :2] for b in bad], [0], tmp_path / "b.csv",
                     feature_names=names[:2])
    Xa, ya = read_traces_csv(tmp_path / "a.csv")
    Xb, yb = read_traces_csv(tmp_path / "b.csv")
    with pytest.raises(ValueError, match=r"demonstration 1 has columns \['safe', 'picked'\], "
                                         r"but demonstration 0 has .*: demonstration 1 lacks "
                                         r"the proposition 'placed' seen in demonstration 0"):
        BSIClassifier(random_state=0).fit(Xa + Xb, np.concatenate([ya, yb]))
    renamed = [x.rename(columns={"placed": "done"}) for x in Xa]
    with pytest.raises(ValueError, match="lacks the proposition 'placed' seen in demonstration "
                                         "0; demonstration 1 has the proposition 'done' not "
                                         "seen in demonstration 0"):
        check_traces(Xa + renamed)


def test_labels():
    y01, classes = check_labels(None, 3)
    assert y01.tolist() == [1, 1, 1] and classes.tolist() == [0, 1]
    with pytest.raises(ValueError, match="only unacceptable"):
        check_labels([0, 0], 2)
    with pytest.raises(ValueError, match="Only binary classification is supported"):
        check_labels([0, 1, 2], 3)
    with pytest.raises(ValueError, match="pos_label"):
        check_labels(["good", "bad"], 2)
    y01, classes = check_labels(["good", "bad", "good"], 3, pos_label="good")
    assert y01.tolist() == [1, 0, 1] and classes.tolist() == ["bad", "good"]
    with pytest.raises(ValueError, match="2 labels but there are 3"):
        check_labels([0, 1], 3)


def test_roles():
    r = resolve_roles(["b", 0], ["c"], {"c": "a"}, 3, ["a", "b", "c"])
    assert r.global_idx.tolist() == [1, 0] and r.condition_idx.tolist() == [0]
    with pytest.raises(ValueError, match="global_candidates: unknown proposition 'z'"):
        resolve_roles(["z"], None, None, 3, ["a", "b", "c"])
    with pytest.raises(ValueError, match="subtasks: proposition index 7 is out of range"):
        resolve_roles(None, [7], None, 3)
    with pytest.raises(ValueError, match="conditions: 'a' is not one of the subtasks"):
        resolve_roles(None, ["c"], {"a": "b"}, 3, ["a", "b", "c"])
    with pytest.raises(ValueError, match="listed more than once"):
        resolve_roles([0, 0], None, None, 3)
    with pytest.raises(ValueError, match="conditions must be None or a mapping"):
        resolve_roles(None, None, [1], 3)


@pytest.mark.parametrize("conditions, names", [({2: 2}, None), ({"c": "c"}, ["a", "b", "c"]),
                                               ({"c": 2}, ["a", "b", "c"])])
def test_a_subtask_is_not_its_own_condition(conditions, names):
    # Issue 21: {2: 2} was accepted and gave the clause (2 -> F(2)), which always holds.
    with pytest.raises(ValueError, match=r"conditions\[.*\]: subtask .* cannot be its own "
                                         "condition"):
        resolve_roles(None, None, conditions, 3, names)
    with pytest.raises(ValueError, match="cannot be its own condition"):
        BSIClassifier(conditions=conditions).fit(
            [pd.DataFrame(np.eye(3, dtype=int), columns=names or range(3))])


@pytest.mark.parametrize(
    "params, match",
    [
        ({"prior": "dag"}, "prior must be one of"),
        ({"likelihood": "x"}, "likelihood must be one of"),
        ({"p_part": 1.5}, r"p_part must be a number in \[0.0, 1.0\]"),
        ({"n_new": 0}, r"n_new must be a number in \(0.0, inf\)"),
        ({"epsilon": 1.0}, r"epsilon must be a number in \(0.0, 1.0\) or None"),
        ({"n_samples": 0}, r"n_samples must be one of \[.auto.\] or an integer >= 1"),
        ({"n_chains": 2.5}, "n_chains must be an integer"),
        ({"inference": "vi"}, "inference must be one of"),
        ({"n_jobs": 0}, "n_jobs must be None or a non-zero integer"),
    ],
)
def test_bad_parameters(params, match):
    with pytest.raises(ValueError, match=match):
        BSIClassifier(**params).fit([np.ones((2, 2))])


def test_predict_checks_propositions():
    clf = BSIClassifier(random_state=0).fit([pd.DataFrame([[1, 0]], columns=["p", "q"])])
    with pytest.raises(ValueError, match="X has 3 features, but BSIClassifier is expecting 2"):
        clf.predict([np.ones((2, 3))])
    with pytest.raises(ValueError, match="feature names should match"):
        clf.predict([pd.DataFrame([[1, 0]], columns=["q", "p"])])
    with pytest.warns(UserWarning, match="does not have valid feature names"):
        clf.predict([np.ones((2, 2))])
    with pytest.raises(ValueError, match="inference='exact' needs"):
        BSIClassifier(roles="all", inference="exact",
                      max_exact_hypotheses=10).fit([np.ones((2, 3))])


@pytest.mark.parametrize("method", ["predict", "predict_proba"])
def test_predict_names_the_missing_and_unseen_columns(method):
    cols = ["safe", "picked", "placed"]
    X = [pd.DataFrame([[1, 0, 0], [1, 1, 0], [1, 1, 1]], columns=cols),
         pd.DataFrame([[1, 0, 0], [1, 0, 1], [1, 1, 1]], columns=cols)]
    clf = BSIClassifier(random_state=0).fit(X, [1, 0])
    predict = getattr(clf, method)
    with pytest.raises(ValueError, match=r"X lacks the proposition 'picked' seen in fit\.\n"
                                         r"Fitted with: \['safe', 'picked', 'placed'\]"):
        predict([x[["safe", "placed"]] for x in X])
    with pytest.raises(ValueError, match="X lacks the propositions 'picked', 'placed' seen"):
        predict([x[["safe"]] for x in X])
    with pytest.raises(ValueError, match="X has the proposition 'extra' not seen in fit"):
        predict([x.assign(extra=0) for x in X])
    with pytest.raises(ValueError, match="lacks the proposition 'safe' seen in fit; X has "
                                         "the proposition 'Safe' not seen in fit"):
        predict([x.rename(columns={"safe": "Safe"}) for x in X])
    with pytest.raises(ValueError, match="in another order"):
        predict([x[cols[::-1]] for x in X])
    # a long-format frame is checked the same way
    long = pd.concat([x.assign(demo_id=i) for i, x in enumerate(X)])
    np.testing.assert_array_equal(getattr(clf, method)(long), predict(X))
    with pytest.raises(ValueError, match="X lacks the proposition 'placed' seen in fit"):
        predict(long.drop(columns="placed"))


def test_single_dataframe_is_rejected_unless_long_format():
    df = pd.DataFrame([[1, 0], [0, 1], [1, 1]], columns=["p", "q"])
    with pytest.raises(ValueError, match=r"single DataFrame without a 'demo_id'.*Pass \[df\]"):
        check_traces(df)
    clf = BSIClassifier(random_state=0).fit([df])
    with pytest.raises(ValueError, match=r"Pass \[df\] if it is one demonstration"):
        clf.predict(df)
    # fit(df, y) with one label per row was silently read as length-one traces.
    with pytest.raises(ValueError, match="single DataFrame"):
        BSIClassifier().fit(df, [1, 0, 1])
    assert clf.predict([df]).shape == (1,)
    # A long-format frame (demo_id, optional t) is split into demonstrations.
    long = pd.DataFrame({"demo_id": [7, 7, 3], "t": [1, 0, 0], "p": [0, 1, 1], "q": [1, 0, 0]})
    t = check_traces(long)
    assert t.n_demos == 2 and t.lengths.tolist() == [2, 1] and list(t.feature_names) == ["p", "q"]
    assert t.trace(0).tolist() == [[True, False], [False, True]]
    no_t = check_traces(long.drop(columns="t"))
    assert no_t.trace(0).tolist() == [[False, True], [True, False]]
    with pytest.raises(ValueError, match="'label' column; split it first"):
        check_traces(long.assign(label=1))
    # The 2-D format of scikit-learn stays: arrays and nested lists of numbers.
    assert check_traces(np.array([[1, 0], [0, 1]])).lengths.tolist() == [1, 1]
    assert check_traces([[1, 0], [0, 1]]).lengths.tolist() == [1, 1]
    numeric = check_traces([np.array([[0.5, 2.0]])], numeric=True)
    assert numeric.data.dtype == np.float64 and numeric.data.tolist() == [[0.5, 2.0]]
    rows = check_traces(df, frame_as_rows=True)
    assert rows.n_demos == 3 and list(rows.feature_names) == ["p", "q"]


def test_list_of_1d_arrays_is_rejected_with_a_reshape_hint():
    X = [np.array([0, 1, 1]), np.array([1, 1, 0])]
    with pytest.raises(ValueError, match=r"demonstration 0 is a 1-D array of shape \(3,\).*"
                                         r"x\.reshape\(-1, 1\)"):
        check_traces(X)
    with pytest.raises(ValueError, match="1-D array"):
        check_traces([pd.Series([0, 1])])
    assert check_traces([x.reshape(-1, 1) for x in X]).lengths.tolist() == [3, 3]


def test_messages_name_the_column_demonstration_and_step():
    good = pd.DataFrame({"safe": [1, 1], "mode": [0, 1]})
    nan = pd.DataFrame({"safe": [1.0, np.nan], "mode": [0, 1]})
    with pytest.raises(ValueError, match="demonstration 1, step 1, proposition 'safe' is nan"):
        check_traces([good, nan])
    text = pd.DataFrame({"safe": [1, 1], "mode": ["no", "yes"]})
    with pytest.raises(ValueError, match="demonstration 0, step 0, proposition 'mode' has the "
                                         "non-numeric value 'no'"):
        check_traces([text])
    two = pd.DataFrame({"safe": [1, 2], "mode": [0, 1]})
    with pytest.raises(ValueError, match="demonstration 1, step 1, proposition 'safe' has val"):
        check_traces([good, two])
    with pytest.raises(ValueError, match="demonstration 2, step 0, proposition 1 has value 5"):
        check_traces(np.array([[0, 1], [1, 0], [1, 5]]))
    with pytest.raises(ValueError, match="duplicate column names"):
        check_traces([pd.DataFrame([[1, 0]], columns=["a", "a"])])


def test_a_time_column_gets_time_advice_not_binarize():
    frame = pd.DataFrame({"time": [0.5, 1.0, 1.5], "a": [1, 0, 1]})
    with pytest.raises(ValueError, match="looks like a time stamp") as exc:
        BSIClassifier().fit([frame])
    assert "set binarize" not in str(exc.value)
    with pytest.raises(ValueError, match="set binarize=<threshold>"):
        BSIClassifier().fit([pd.DataFrame({"speed": [3.0, 1.0], "a": [1, 0]})])
