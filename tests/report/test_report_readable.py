"""Reports show the MAP readably: orders as chains, untested clauses marked (issue 20)."""

import numpy as np
import pytest

from bsi_sklearn import BSIClassifier, Specification
from bsi_sklearn.report import explain
from bsi_sklearn.report.wording import unicode_ltl

NAMES = ["safe", "a", "b", "c"]


def _demo(events, T=4):
    """safe always holds and c from the first step, in every demonstration."""
    tr = np.zeros((T, 4), dtype=np.uint8)
    tr[:, 0] = tr[:, 3] = 1
    for p, t in events:
        tr[t:, NAMES.index(p)] = 1
    return tr


X = [_demo([("a", 1), ("b", 2)]), _demo([("a", 1), ("b", 3)]),
     _demo([("b", 1), ("a", 2)]), _demo([("a", 1)])]
Y = [1, 1, 0, 0]
FULL = "G(0) & F(1) & F(2) & F(3) & (!2 U 1) & (!1 U 3) & (!2 U 3)"
READABLE = "F(2) & (!2 U 1)  [untested: G(0) & F(1) & F(3) & (!1 U 3)]"


@pytest.fixture(scope="module")
def report():
    clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2, 3], random_state=0).fit(X, Y)
    return explain(clf, X, Y, top_k=3)


def test_report_fields(report):
    assert report.ltl == FULL and report.readable == READABLE
    clauses = report.clauses
    assert [k for k in clauses.index if clauses.loc[[k], "implied"].item()] == [("U", 3, 2)]
    assert {k for k in clauses.index if clauses.loc[[k], "vacuous"].item()} == {
        ("G", 0), ("F", 1), ("F", 3), ("U", 3, 1), ("U", 3, 2)}
    assert report.order_edges == [(1, 2), (3, 1)]
    assert report.top["readable"].iloc[0] == READABLE
    assert report.top["ltl"].iloc[0] == FULL


def test_documents_show_the_readable_formula_and_the_full_one(report, tmp_path):
    md = report.to_markdown(tmp_path).read_text(encoding="utf-8")
    assert f"```text\n{READABLE}\n```" in md and f"```text\n{FULL}\n```" in md
    assert md.index(READABLE) < md.index(FULL)
    assert "1 order implied by the others" in md and "4 untested clauses set apart" in md
    # the clause lists leave the implied order out and mark the untested clauses
    assert "`(!2 U 3)`" not in md
    assert md.count("; untested)") == 4
    assert r"**◇(2) ∧ (¬2 U 1)  \[untested: □(0) ∧ ◇(1) ∧ ◇(3) ∧ (¬1 U 3)\]**" in md


def test_a_report_without_anything_to_shorten_shows_one_formula(tmp_path):
    Xs = [_demo([("a", 1), ("b", 2)]), _demo([("b", 1), ("a", 2)]), _demo([])]
    Xs[1][2, 0] = 0  # unsafe once
    clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], random_state=0).fit(
        Xs, [1, 0, 0])
    assert clf.vacuous_clauses_ == frozenset()
    rep = explain(clf)
    assert rep.readable == rep.ltl
    md = rep.to_markdown(tmp_path).read_text(encoding="utf-8")
    assert md.count("```text") == 1 and "untested" not in md


def test_unicode_ltl_readable():
    spec = Specification(globals=["s"], orders=[("a", "b"), ("b", "c")],
                         conditions={"a": "p"})
    assert unicode_ltl(spec) == "□(s) ∧ (p → (¬b U a)) ∧ (p → (¬c U a)) ∧ (¬c U b)"
    assert unicode_ltl(spec, chains=True) == "□(s) ∧ (p → (¬b U a)) ∧ (¬c U b)"
    assert unicode_ltl(spec, chains=True, vacuous={("G", "s")}) == \
        "(p → (¬b U a)) ∧ (¬c U b)  [untested: □(s)]"


def test_a_report_on_negated_columns_never_shows_a_double_negation(tmp_path):
    import pandas as pd

    from bsi_sklearn.data.preprocessing import NegationAugmenter

    def demo(a_at, b_until, T=4):  # b holds until a comes in the acceptable ones
        a, b = np.zeros(T, bool), np.zeros(T, bool)
        a[a_at:], b[:b_until] = True, True
        return pd.DataFrame({"a": a, "b": b})

    X, y = [demo(2, 3), demo(1, 2), demo(2, 1), demo(3, 1)], [1, 1, 0, 0]
    aug = NegationAugmenter(propositions=["b"]).fit(X)
    Xa = aug.transform(X)
    clf = BSIClassifier(global_candidates=[], subtasks=["a", "!b"], random_state=0).fit(Xa, y)
    assert clf.map_specification_.to_ltl() == "F(!b) & F(a) & (!!b U a)"  # recorded form
    for negations in (None, aug.negations_):
        rep = explain(clf, Xa, y, negations=negations)
        assert rep.readable == "(b U a)  [untested: F(!b) & F(a)]"
        assert rep.sentences == ["Eventually, b does not hold.", "Eventually, a holds.",
                                 "b holds until a holds."]
        md = rep.to_markdown(tmp_path).read_text(encoding="utf-8")
        assert "!!" not in md and "¬!" not in md
        assert "```text\nF(!b) & F(a) & (b U a)\n```" in md
        assert "(b U a)  \\[untested: ◇(¬b) ∧ ◇(a)\\]" in md
    plain = explain(clf, negations=False)
    assert plain.readable == '(!"!b" U a)  [untested: F("!b") & F(a)]'
    assert plain.sentences[-1] == "a holds before !b holds."
