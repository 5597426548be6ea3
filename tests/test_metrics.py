import numpy as np
import pytest

from bsi_sklearn.metrics import (
    OrderCounts,
    best_similarity,
    classify_orders,
    expected_order_counts,
    expected_similarity,
    jaccard_similarity,
)
from bsi_sklearn.specification import Specification

TRUTH = Specification(
    globals=["t1", "t2"],
    eventuals=["a", "b", "c"],
    orders=[("a", "b"), ("b", "c")],  # closed: (a,b), (b,c), (a,c)
    conditions={"a": "pa", "b": "pb", "c": "pc"},
)


class FakePosterior:
    """Duck type of bsi_sklearn.posterior.Posterior."""

    def __init__(self, pairs):
        pairs = sorted(pairs, key=lambda p: -p[1])
        self.specifications = [s for s, _ in pairs]
        self.probabilities = np.array([p for _, p in pairs])

    def top(self, k):
        return list(zip(self.specifications[:k], self.probabilities[:k], strict=True))


def test_jaccard_identical_and_empty():
    assert jaccard_similarity(TRUTH, TRUTH) == 1.0
    assert jaccard_similarity(Specification(), Specification()) == 1.0
    assert jaccard_similarity(Specification(), TRUTH) == 0.0
    assert jaccard_similarity(TRUTH, Specification()) == 0.0


def test_jaccard_exact_values():
    # truth has 2 + 3 + 3 = 8 clauses
    spec = Specification(globals=["t1"], eventuals=["a", "b", "d"], orders=[("a", "b")])
    # spec clauses: G t1, F a, F b, F d, U(a,b) -> 5; intersection 4; union 8 + 1 = 9
    assert jaccard_similarity(spec, TRUTH) == pytest.approx(4 / 9)
    # symmetric
    assert jaccard_similarity(TRUTH, spec) == pytest.approx(4 / 9)
    # a reversed order shares nothing with the true one
    rev = Specification(orders=[("b", "a")])
    assert jaccard_similarity(rev, Specification(orders=[("a", "b")])) == 0.0


def test_jaccard_ignores_conditions_and_construction_order():
    s1 = Specification(eventuals=["a"], orders=[("a", "b"), ("b", "c")])
    s2 = Specification(eventuals=["a"], orders=[("b", "c"), ("a", "c"), ("a", "b")],
                       conditions={"a": "pa"})
    assert jaccard_similarity(s1, s2) == 1.0


def test_jaccard_bad_input():
    with pytest.raises(ValueError, match="spec"):
        jaccard_similarity("G(a)", TRUTH)
    with pytest.raises(ValueError, match="truth"):
        jaccard_similarity(TRUTH, None)


def _posterior_pairs():
    s_half = Specification(globals=["t1", "t2"], eventuals=["a", "b", "c"])  # 5/8
    s_none = Specification(orders=[("c", "a")])  # 0
    return [(s_half, 0.5), (TRUTH, 0.3), (s_none, 0.2)]


@pytest.mark.parametrize("kind", ["fake", "list", "dict"])
def test_expected_and_best_similarity(kind):
    pairs = _posterior_pairs()
    post = {"fake": FakePosterior(pairs), "list": pairs, "dict": dict(pairs)}[kind]
    assert expected_similarity(post, TRUTH) == pytest.approx(0.5 * 5 / 8 + 0.3)
    assert best_similarity(post, TRUTH, k=1) == pytest.approx(5 / 8)
    assert best_similarity(post, TRUTH, k=2) == 1.0
    assert best_similarity(post, TRUTH) == 1.0


def test_unsorted_and_unnormalised_pairs():
    s_half, truth, s_none = (s for s, _ in _posterior_pairs())
    pairs = [(s_none, 2.0), (truth, 3.0), (s_half, 5.0)]
    assert expected_similarity(pairs, TRUTH) == pytest.approx(0.5 * 5 / 8 + 0.3)
    assert best_similarity(pairs, TRUTH, k=1) == pytest.approx(5 / 8)


def test_single_specification_is_a_point_mass():
    assert expected_similarity(TRUTH, TRUTH) == 1.0


@pytest.mark.parametrize(
    "post, match",
    [
        ([], "empty"),
        ([(TRUTH, -0.1)], "non-negative"),
        ([(TRUTH, float("nan"))], "finite"),
        ([(TRUTH, 0.0)], "zero"),
        ([("x", 1.0)], "entry 0"),
        ([(TRUTH,)], "entry 0"),
        (3, "posterior"),
    ],
)
def test_bad_posteriors(post, match):
    with pytest.raises(ValueError, match=match):
        expected_similarity(post, TRUTH)


@pytest.mark.parametrize("k", [0, -1, 1.5, True, "5"])
def test_bad_k(k):
    with pytest.raises(ValueError, match="k must"):
        best_similarity([(TRUTH, 1.0)], TRUTH, k=k)


def test_classify_orders_exact_sets():
    spec = Specification(orders=[("a", "b"), ("c", "b"), ("d", "a")])
    # closure: (a,b), (c,b), (d,a), (d,b)
    res = classify_orders(spec, TRUTH)
    assert res.correct == {("a", "b")}
    assert res.incorrect == {("c", "b")}
    assert res.extra == {("d", "a"), ("d", "b")}
    assert res.counts == OrderCounts(1, 1, 2)
    full = classify_orders(TRUTH, TRUTH)
    assert full.counts == (3, 0, 0)
    none = classify_orders(Specification(globals=["t1"]), TRUTH)
    assert none.counts == (0, 0, 0)


def test_classify_orders_full_reverse():
    rev = Specification(orders=[("c", "b"), ("b", "a")])
    assert classify_orders(rev, TRUTH).counts == (0, 3, 0)


def test_expected_order_counts():
    pairs = _posterior_pairs()
    counts = expected_order_counts(FakePosterior(pairs), TRUTH)
    # s_half: 0 orders; TRUTH: 3 correct; s_none: (c,a) incorrect
    assert counts.correct == pytest.approx(0.9)
    assert counts.incorrect == pytest.approx(0.2)
    assert counts.extra == pytest.approx(0.0)
    assert isinstance(counts, OrderCounts)
