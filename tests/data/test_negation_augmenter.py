"""NegationAugmenter / add_negations: negated propositions as new columns."""

import pickle

import numpy as np
import pandas as pd
import pytest
from poi_problems import make_absence_problem
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.pipeline import make_pipeline
from sklearn.utils.estimator_checks import parametrize_with_checks

from bsi_sklearn import BSIClassifier, Specification
from bsi_sklearn.data.preprocessing import NegationAugmenter, add_negations
from bsi_sklearn.ltl import parse_ltl


@parametrize_with_checks(
    [NegationAugmenter(binarize=0.0)],
    expected_failed_checks=lambda est: {
        "check_transformer_preserve_dtypes": "the output is boolean propositions by design",
    },
)
def test_sklearn_compatible(estimator, check):
    check(estimator)


def frames(seed=0, n=5, names=("a", "b", "c")):
    rng = np.random.default_rng(seed)
    return [pd.DataFrame(rng.random((k, len(names))) < 0.5,
                         columns=list(names), index=np.arange(100, 100 + k))
            for k in rng.integers(1, 6, size=n)]


def test_list_of_frames_keeps_names_and_index():
    X = frames()
    out = NegationAugmenter().fit_transform(X)
    assert isinstance(out, list) and len(out) == len(X)
    for x, o in zip(X, out):
        assert list(o.columns) == ["a", "b", "c", "!a", "!b", "!c"]
        assert o.index.equals(x.index)
        np.testing.assert_array_equal(o[["a", "b", "c"]].to_numpy(), x.to_numpy())
        np.testing.assert_array_equal(o[["!a", "!b", "!c"]].to_numpy(), ~x.to_numpy())


def test_subset_by_name_or_index_and_prefix():
    X = frames()
    aug = NegationAugmenter(propositions=["c", "a"], prefix="not_").fit(X)
    np.testing.assert_array_equal(aug.negated_, [2, 0])
    assert aug.get_feature_names_out().tolist() == ["a", "b", "c", "not_c", "not_a"]
    out = aug.transform(X)
    np.testing.assert_array_equal(out[0]["not_c"], ~X[0]["c"])
    aug_idx = NegationAugmenter(propositions=[1]).fit(X)
    assert aug_idx.get_feature_names_out().tolist() == ["a", "b", "c", "!b"]


@pytest.mark.parametrize("kind", ["3d", "2d", "list", "nested", "frame", "object"])
def test_output_mirrors_input_container(kind):
    rng = np.random.default_rng(3)
    cube = rng.integers(0, 2, size=(4, 3, 2))
    X = {"3d": cube, "2d": cube[:, 0, :], "list": list(cube), "nested": cube[:, 0, :].tolist(),
         "frame": pd.DataFrame(cube[:, 0, :], columns=["p", "q"]),
         "object": np.array([cube[0], cube[1, :2]], dtype=object)}[kind]
    out = add_negations(X)
    if kind == "3d":
        assert out.shape == (4, 3, 4)
        np.testing.assert_array_equal(out[..., 2:], 1 - cube)
    elif kind in ("2d", "nested"):
        assert isinstance(out, np.ndarray) and out.shape == (4, 4)
        np.testing.assert_array_equal(out[:, 2:], 1 - cube[:, 0, :])
    elif kind == "frame":
        assert list(out.columns) == ["p", "q", "!p", "!q"] and out.shape == (4, 4)
    elif kind == "list":
        assert isinstance(out, list) and [o.shape for o in out] == [(3, 4)] * 4
    else:
        assert [o.shape for o in out] == [(3, 4), (2, 4)]
    first = out[0] if isinstance(out, list) else out
    dtypes = first.dtypes if hasattr(first, "dtypes") else [first.dtype]
    assert all(dt == np.bool_ for dt in dtypes)


def test_unnamed_negation_names_follow_sklearn():
    aug = NegationAugmenter(propositions=[0]).fit(np.zeros((2, 3, 2)))
    assert aug.get_feature_names_out().tolist() == ["x0", "x1", "!x0"]
    assert aug.get_feature_names_out(["u", "v"]).tolist() == ["u", "v", "!u"]
    assert not hasattr(aug, "feature_names_in_")


def test_errors():
    X = frames()
    with pytest.raises(ValueError, match="unknown proposition 'z'"):
        NegationAugmenter(propositions=["z"]).fit(X)
    with pytest.raises(ValueError, match="listed more than once"):
        NegationAugmenter(propositions=["a", 0]).fit(X)
    with pytest.raises(ValueError, match="prefix must be a non-empty string"):
        NegationAugmenter(prefix="").fit(X)
    with pytest.raises(ValueError, match="binarize must be None or a number"):
        NegationAugmenter(binarize="x").fit(X)
    clash = [pd.DataFrame({"a": [1], "!a": [0]})]
    with pytest.raises(ValueError, match="'!a' already exists"):
        NegationAugmenter(propositions=["a"]).fit(clash)
    with pytest.raises(NotFittedError):
        NegationAugmenter().transform(X)
    aug = NegationAugmenter().fit(X)
    with pytest.raises(ValueError, match="feature names should match"):
        aug.transform([x.rename(columns={"a": "z"}) for x in X])
    with pytest.raises(ValueError, match="expecting 3 features"):
        aug.transform([np.zeros((2, 2))])
    with pytest.raises(ValueError, match="demonstration 1, step 0, proposition 0 has value 3"):
        aug.transform([np.zeros((2, 3)), np.full((1, 3), 3)])


def test_pickle_and_clone():
    aug = NegationAugmenter(propositions=["b"]).fit(frames())
    again = pickle.loads(pickle.dumps(aug))
    X = frames(1)
    for a, b in zip(aug.transform(X), again.transform(X)):
        pd.testing.assert_frame_equal(a, b)
    assert clone(aug).get_params() == aug.get_params()


def test_pipeline_learns_an_absence_pattern():
    """G(!p) is out of the template without negations, learnt with them."""
    arrays, y = make_absence_problem()  # q always holds in every demonstration
    X = [pd.DataFrame(t, columns=["p", "q"]) for t in arrays]
    pipe = make_pipeline(NegationAugmenter(), BSIClassifier(random_state=0, n_jobs=1))
    pipe.fit(X, y)
    spec = pipe[-1].map_specification_
    target = parse_ltl("G(!p) & G(q)").to_specification(
        names=pipe[0].get_feature_names_out())
    assert target == Specification(globals=["!p", "q"])
    assert target.globals <= spec.globals
    assert pipe.score(X, y) == 1.0
    # Without negations the learner cannot separate the classes.
    plain = BSIClassifier(random_state=0, n_jobs=1).fit(X, y)
    assert plain.score(X, y) < 1.0


def test_negations_name_each_new_column_and_the_map_reads_without_double_negations():
    aug = NegationAugmenter().fit(frames())
    assert aug.negations_ == {f"!{n}": n for n in aug.feature_names_in_}
    assert NegationAugmenter(prefix="no_", propositions=[0]).fit(frames()).negations_ == {
        "no_a": "a"}
    assert NegationAugmenter().fit(np.zeros((2, 3, 2))).negations_ == {2: 0, 3: 1}
    spec = Specification(globals=["!a"], orders=[("b", "!a"), ("a", "!a")])
    assert spec.readable(negations=aug.negations_) == spec.readable() == "G(!a) & a & (a U b)"
