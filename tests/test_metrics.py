import numpy as np
import pytest

from bsi_sklearn.metrics import (
    OrderCounts,
    best_similarity,
    classify_orders,
    expected_order_counts,
    expected_similarity,
    jaccard_similarity,
    similarity_summary,
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


# ---------------------------------------------------------------- one-pass summary
def test_similarity_summary_exact_numbers():
    pairs = _posterior_pairs()  # s_half 0.5 (5/8), TRUTH 0.3, s_none 0.2
    summary = similarity_summary(pairs, TRUTH, k=5)
    assert summary["expected_similarity"] == pytest.approx(0.5 * 5 / 8 + 0.3)
    assert summary["best_similarity"] == 1.0
    assert summary["map_similarity"] == pytest.approx(5 / 8)
    assert summary["truth_rank"] == 2
    assert summary["truth_probability"] == pytest.approx(0.3)
    assert summary["truth_in_top_k"] and not summary["map_is_truth"]
    assert summary["n_specifications"] == 3
    assert summary["correct_orders"] == pytest.approx(0.9)
    assert summary["incorrect_orders"] == pytest.approx(0.2)
    assert summary["extra_orders"] == pytest.approx(0.0)
    assert similarity_summary(pairs, TRUTH, k=1)["truth_in_top_k"] is False
    absent = similarity_summary([(Specification(), 1.0)], TRUTH)
    assert absent["truth_rank"] is None and absent["truth_probability"] == 0.0


def test_summary_truth_rank_ignores_conditions():
    bare = Specification(globals=TRUTH.globals, eventuals=TRUTH.eventuals,
                         orders=TRUTH.orders)
    assert similarity_summary([(bare, 1.0)], TRUTH)["map_is_truth"]


def _random_spec(rng, props):
    g = [p for p in props[:3] if rng.random() < 0.5]
    e = [p for p in props[3:] if rng.random() < 0.5]
    perm = list(rng.permutation(props[3:]))
    orders = [(perm[i], perm[j]) for i in range(len(perm)) for j in range(i + 1, len(perm))
              if rng.random() < 0.3]
    return Specification(globals=g, eventuals=e, orders=orders)


class MatrixPosterior(FakePosterior):
    """A posterior that also offers the clause-matrix fast path."""

    def __init__(self, pairs, keys):
        super().__init__(pairs)
        self._keys = keys

    def clause_keys(self):
        return self._keys

    def clause_matrix(self):
        return np.array([[k in s.clauses() for k in self._keys] for s in self.specifications])


def test_fast_path_matches_generic_path():
    rng = np.random.default_rng(0)
    props = ["g1", "g2", "g3", "a", "b", "c", "d"]
    subtasks = props[3:]
    keys = [("G", p) for p in props[:3]] + [("F", w) for w in subtasks]
    keys += [("U", a, b) for a in subtasks for b in subtasks if a != b]
    specs = list({_random_spec(rng, props) for _ in range(200)})
    probs = rng.random(len(specs))
    pairs = list(zip(specs, probs / probs.sum(), strict=True))
    # a truth that mentions a clause outside the candidates ("G", "zz") too
    truth = Specification(globals=["g1", "zz"], eventuals=["a", "b", "c"],
                          orders=[("a", "b"), ("b", "c")])
    fast, slow = MatrixPosterior(pairs, keys), FakePosterior(pairs)
    assert similarity_summary(fast, truth) == pytest.approx(similarity_summary(slow, truth))
    manual = sum(p * jaccard_similarity(s, truth) for s, p in pairs)
    assert expected_similarity(fast, truth) == pytest.approx(manual)
    counts = np.array([classify_orders(s, truth).counts for s, _ in pairs]).T @ \
        np.array([p for _, p in pairs])
    assert tuple(expected_order_counts(fast, truth)) == pytest.approx(tuple(counts))


def test_fast_path_shape_mismatch():
    post = MatrixPosterior([(TRUTH, 1.0)], [("G", "t1")])
    post.clause_matrix = lambda: np.zeros((1, 3), bool)
    with pytest.raises(ValueError, match="clause_matrix"):
        expected_similarity(post, TRUTH)


def test_with_a_fitted_classifier():
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.datasets import make_poi_threat_demos

    data = make_poi_threat_demos(3, n_demos=4, n_threats=2, random_state=0)
    clf = BSIClassifier(prior="sets_of_chains", random_state=0, **data.roles)
    post = clf.fit(data.traces).posterior_
    truth = data.specification
    pairs = list(zip(post.specifications, post.probabilities, strict=True))
    assert expected_similarity(post, truth) == pytest.approx(expected_similarity(pairs, truth))
    summary = similarity_summary(post, truth)
    assert summary["map_similarity"] == jaccard_similarity(clf.map_specification_, truth)
    assert summary["n_specifications"] == len(pairs)
