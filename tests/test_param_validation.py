import argparse
import math
from numbers import Integral, Real

import numpy as np
import pytest

from bsi_sklearn import BSIClassifier, Specification
from bsi_sklearn.data.preprocessing import NegationAugmenter
from bsi_sklearn.param_validation import (
    NONZERO_INTEGER,
    Interval,
    InvalidParameterError,
    Options,
    Satisfies,
    StrOptions,
    check_options,
    describe,
    is_satisfied,
    validate_params,
)


# ---------------------------------------------------------------- intervals
@pytest.mark.parametrize("value, inside", [
    (0, True), (1, True), (0.5, True), (np.float32(0.25), True), (np.int64(1), True),
    (-1e-12, False), (1.0000001, False), (True, False), (False, False), (np.bool_(True), False),
    (float("nan"), False), (math.inf, False), ("0.5", False), (None, False),
])
def test_real_interval_closed(value, inside):
    assert Interval(Real, 0, 1, closed="both").is_satisfied_by(value) is inside


@pytest.mark.parametrize("closed, left_in, right_in", [
    ("both", True, True), ("left", True, False), ("right", False, True),
    ("neither", False, False),
])
def test_interval_closed_ends(closed, left_in, right_in):
    for t in (Integral, Real):
        iv = Interval(t, 0, 3, closed=closed)
        assert iv.is_satisfied_by(0) is left_in
        assert iv.is_satisfied_by(3) is right_in
        assert iv.is_satisfied_by(2)


def test_integer_interval_rejects_floats_and_bools():
    iv = Interval(Integral, 1, None, closed="left")
    assert iv.is_satisfied_by(1) and iv.is_satisfied_by(np.int32(7)) and iv.is_satisfied_by(10**30)
    for bad in (0, 1.0, 2.5, True, np.bool_(True), "3", None, float("nan")):
        assert not iv.is_satisfied_by(bad)


def test_infinity_needs_an_explicit_closed_bound():
    assert not Interval(Real, 0, None, closed="left").is_satisfied_by(math.inf)
    assert not Interval(Real, None, None, closed="neither").is_satisfied_by(-math.inf)
    assert not Interval(Real, 0, math.inf, closed="left").is_satisfied_by(math.inf)
    assert Interval(Real, 0, math.inf, closed="both").is_satisfied_by(math.inf)
    assert not Interval(Real, 0, math.inf, closed="both").is_satisfied_by(-math.inf)
    assert Interval(Real, -math.inf, 0, closed="left").is_satisfied_by(-math.inf)
    assert not Interval(Real, -math.inf, math.inf, closed="both").is_satisfied_by(math.nan)


@pytest.mark.parametrize("interval, words", [
    (Interval(Real, 0, 1, closed="both"), "a number in [0, 1]"),
    (Interval(Real, 0.0, 1.0, closed="left"), "a number in [0.0, 1.0)"),
    (Interval(Real, 0.0, math.inf, closed="neither"), "a number in (0.0, inf)"),
    (Interval(Real, 0, None, closed="left"), "a finite number >= 0"),
    (Interval(Real, 0, None, closed="neither"), "a positive number"),
    (Interval(Real, 1, None, closed="neither"), "a finite number > 1"),
    (Interval(Real, None, 2, closed="right"), "a finite number <= 2"),
    (Interval(Real, None, None, closed="neither"), "a finite number"),
    (Interval(Integral, 1, None, closed="left"), "an integer >= 1"),
    (Interval(Integral, 0, None, closed="left"), "an integer >= 0"),
    (Interval(Integral, 0, None, closed="neither"), "an integer > 0"),
    (Interval(Integral, 2, 5, closed="both"), "an integer in [2, 5]"),
    (Interval(Integral, None, 5, closed="neither"), "an integer < 5"),
    (Interval(Integral, None, None, closed="neither"), "an integer"),
])
def test_interval_words(interval, words):
    assert str(interval) == words
    assert describe(interval) == words


@pytest.mark.parametrize("args, kwargs", [
    ((float, 0, 1), {"closed": "both"}),
    ((Real, 0, 1), {"closed": "open"}),
    ((Real, 2, 1), {"closed": "both"}),
    ((Real, math.nan, 1), {"closed": "both"}),
    ((Integral, True, None), {"closed": "left"}),
])
def test_bad_interval_definitions(args, kwargs):
    with pytest.raises(ValueError):
        Interval(*args, **kwargs)


# ---------------------------------------------------------------- other constraints
def test_options():
    opts = StrOptions(("b", "a"))
    assert opts.is_satisfied_by("a") and not opts.is_satisfied_by("c")
    assert not opts.is_satisfied_by(["a"])
    assert str(opts) == "one of ['b', 'a']"
    assert str(StrOptions({"y", "x"})) == "one of ['x', 'y']"
    nums = Options(Integral, (1, 2, 3))
    assert nums.is_satisfied_by(np.int64(2))
    assert not nums.is_satisfied_by(True) and not nums.is_satisfied_by(2.0)


@pytest.mark.parametrize("constraint, good, bad, words", [
    (None, [None], [0, "", False], "None"),
    ("boolean", [True, np.bool_(False)], [0, 1, "True", None], "a bool"),
    (Integral, [0, np.int8(3)], [True, 1.0], "an integer"),
    (Real, [0, 1.5, np.float32(2)], [True, "1"], "a number"),
    (str, ["", "x"], [b"x", 1], "a string"),
    (dict, [{}], [[], None], "a dict"),
    (Specification, [Specification()], ["G(a)"], "a Specification"),
    (callable, [len, lambda: 0], [1, "f"], "a callable"),
    (NONZERO_INTEGER, [1, -1, np.int64(4)], [0, True, 1.0, None], "a non-zero integer"),
    ("random_state", [None, 0, 2**32 - 1, np.random.RandomState(0)],
     [-1, 2**32, 1.5, "0", np.random.default_rng(0)],
     "None, an integer in [0, 2**32 - 1] or a numpy.random.RandomState"),
])
def test_plain_constraints(constraint, good, bad, words):
    for value in good:
        assert is_satisfied(constraint, value), value
    for value in bad:
        assert not is_satisfied(constraint, value), value
    assert describe(constraint) == words


def test_satisfies_treats_a_failing_predicate_as_false():
    c = Satisfies(lambda v: len(v) > 0, "a non-empty sequence")
    assert c.is_satisfied_by([1]) and not c.is_satisfied_by([]) and not c.is_satisfied_by(3)


def test_unknown_constraints_are_programming_errors():
    with pytest.raises(ValueError, match="unknown constraint"):
        is_satisfied("array-like", 1)
    with pytest.raises(ValueError, match="unknown constraint"):
        describe("array-like")
    with pytest.raises(TypeError, match="list of constraints"):
        validate_params({"a": 1}, {"a": Interval(Real, 0, 1, closed="both")}, "f")


# ---------------------------------------------------------------- validate_params
CONSTRAINTS = {
    "alpha": [Interval(Real, 0, 1, closed="both")],
    "n": [Interval(Integral, 1, None, closed="left"), None],
    "mode": [StrOptions(("fast", "exact"))],
    "weights": [None, StrOptions({"balanced"}), dict],
    "anything": "no_validation",
}


def test_valid_parameters_pass_and_unlisted_ones_are_ignored():
    validate_params({"alpha": 0.3, "n": None, "mode": "fast", "weights": {0: 1.0},
                     "anything": object(), "other": -5}, CONSTRAINTS, "f")
    validate_params({}, CONSTRAINTS, "f")


@pytest.mark.parametrize("params, message", [
    ({"alpha": 2}, "f: alpha must be a number in [0, 1], got 2"),
    ({"alpha": True}, "f: alpha must be a number in [0, 1], got True"),
    ({"alpha": float("nan")}, "f: alpha must be a number in [0, 1], got nan"),
    ({"n": 0}, "f: n must be an integer >= 1 or None, got 0"),
    ({"n": 2.0}, "f: n must be an integer >= 1 or None, got 2.0"),
    ({"mode": "slow"}, "f: mode must be one of ['fast', 'exact'], got 'slow'"),
    ({"weights": "auto"},
     "f: weights must be None, one of ['balanced'] or a dict, got 'auto'"),
])
def test_messages_name_caller_parameter_allowed_and_value(params, message):
    with pytest.raises(InvalidParameterError) as info:
        validate_params(params, CONSTRAINTS, "f")
    assert str(info.value) == message
    name = next(iter(params))
    assert info.value.parameter == name
    assert info.value.caller == "f"
    assert info.value.value is params[name]


def test_error_is_a_value_error_and_a_type_error():
    for exc in (ValueError, TypeError):
        with pytest.raises(exc):
            validate_params({"alpha": "x"}, CONSTRAINTS, "f")


def test_first_bad_parameter_in_declaration_order_is_reported():
    with pytest.raises(InvalidParameterError, match="alpha"):
        validate_params({"mode": "slow", "alpha": -1}, CONSTRAINTS, "f")


def test_no_caller_no_prefix():
    with pytest.raises(InvalidParameterError) as info:
        validate_params({"alpha": 2}, CONSTRAINTS, None)
    assert str(info.value).startswith("alpha must be")


def test_check_options_names_options_as_typed():
    args = argparse.Namespace(n_scenarios=0, noise=0.5, out="x")
    constraints = {"n_scenarios": [Interval(Integral, 1, None, closed="left")],
                   "noise": [Interval(Real, 0, 1, closed="both")],
                   "missing": [None]}
    with pytest.raises(InvalidParameterError) as info:
        check_options(args, constraints)
    assert str(info.value) == "--n-scenarios must be an integer >= 1, got 0"
    assert info.value.parameter == "--n-scenarios"
    args.n_scenarios = 3
    check_options(args, constraints)


def test_check_options_skips_options_not_given_and_does_not_offer_none():
    constraints = {"folds": [Interval(Integral, 2, None, closed="left"), None]}
    check_options(argparse.Namespace(folds=None), constraints)
    with pytest.raises(InvalidParameterError) as info:
        check_options(argparse.Namespace(folds=1), constraints)
    assert str(info.value) == "--folds must be an integer >= 2, got 1"


# ---------------------------------------------------------------- estimators using it
@pytest.mark.parametrize("estimator", [BSIClassifier(), NegationAugmenter()])
def test_estimator_constraints_cover_every_parameter(estimator):
    assert set(estimator._parameter_constraints) == set(estimator.get_params(deep=False))


class _BadType:
    pass


@pytest.mark.parametrize("estimator", [BSIClassifier(), NegationAugmenter()])
def test_estimator_rejects_a_bad_type_for_every_validated_parameter(estimator):
    X = [np.ones((2, 2), dtype=int)]
    for name, constraints in estimator._parameter_constraints.items():
        if constraints == "no_validation":
            continue
        est = estimator.__class__(**{name: _BadType()})
        with pytest.raises(InvalidParameterError, match=rf"{type(est).__name__}: {name} must"):
            est.fit(X)


def test_classifier_parameters_are_validated_before_the_data():
    with pytest.raises(InvalidParameterError, match="BSIClassifier: p_global must be"):
        BSIClassifier(p_global=1.5).fit("not traces")


# ---------------------------------------------------------------- command lines
@pytest.mark.parametrize("argv, message", [
    (["fit", "no_such.trace", "--top", "0"],
     "bsi fit: error: --top must be an integer >= 1, got 0"),
    (["fit", "no_such.trace", "--n-samples", "0"],
     "--n-samples must be one of ['auto'] or an integer >= 1, got 0"),
    (["fit", "no_such.trace", "--seed", "-1"], "--seed must be an integer in [0, 4294967295]"),
])
def test_bsi_options_are_checked_before_any_work(argv, message, capsys):
    from bsi_sklearn.cli import main

    assert main(argv) == 2
    assert message in capsys.readouterr().err


def test_option_type_errors_are_usage_errors(capsys):
    from bsi_sklearn.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["reproduce", "dinner", "--sizes", "3", "0"])
    assert exc.value.code == 2
    assert "argument --sizes: must be an integer >= 1, got 0" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["reproduce", "dinner", "--n-jobs", "x"])
    assert "invalid int value: 'x'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["fit", "no_such.trace", "--n-samples", "many"])
    assert "argument --n-samples: must be 'auto' or an integer, got 'many'" in \
        capsys.readouterr().err


def test_bsi_lfe_report_options_are_checked(tmp_path, capsys):
    lfe_cli = pytest.importorskip("lfe.cli")
    assert lfe_cli.main(["report", "--out", str(tmp_path / "r"), "--n-jobs", "0"]) == 2
    assert "--n-jobs must be a non-zero integer, got 0" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()
