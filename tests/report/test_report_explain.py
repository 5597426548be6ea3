"""explain(): report content, violated clauses, labels, Markdown/HTML output and figures."""

import base64
import re
import xml.etree.ElementTree as ET
from html.parser import HTMLParser

import numpy as np
import pandas as pd
import pytest
from sklearn.metrics import f1_score

from bsi_sklearn import BSIClassifier, Specification
from bsi_sklearn.report import SpecificationReport, explain, violated_clauses
from bsi_sklearn.report.figures import layered_layout

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
NAMES = ["safe", "a", "b", "a_ok"]
DESC = {"safe": "the robot is safe", "a": "the part is picked", "b": "the part is placed",
        "a_ok": "a part is available"}


def demo(events, T=6, a_ok=True, unsafe_at=None):
    tr = np.zeros((T, len(NAMES)), dtype=bool)
    tr[:, 0] = True
    tr[:, 3] = a_ok
    for p, t in events:
        tr[t:, NAMES.index(p)] = True
    if unsafe_at is not None:
        tr[unsafe_at, 0] = False
    return pd.DataFrame(tr, columns=NAMES)


POSITIVES = [demo([("a", 1), ("b", 3)]), demo([("a", 2), ("b", 4)]), demo([("a", 1), ("b", 1)]),
             demo([("b", 2)], a_ok=False), demo([("a", 3), ("b", 2)], a_ok=False),
             demo([("a", 1), ("b", 5)]), demo([("a", 2), ("b", 3)], T=5),
             demo([("b", 1)], a_ok=False)]
NEGATIVES = [demo([("a", 1), ("b", 3)], unsafe_at=4),  # unsafe once
             demo([("b", 1), ("a", 3)]),                # placed before picked
             demo([]),                                  # nothing done
             demo([("a", 2)])]                          # never placed
X = POSITIVES + NEGATIVES
Y = np.array([1] * len(POSITIVES) + [0] * len(NEGATIVES))
MAP = Specification(globals=["safe"], eventuals=["a", "b"], orders=[("a", "b")],
                    conditions={"a": "a_ok"})
CLAUSES = [("G", "safe"), ("F", "a"), ("F", "b"), ("U", "a", "b")]
CLAUSE_LTL = ["G(safe)", "(a_ok -> F(a))", "F(b)", "(a_ok -> (!b U a))"]
SENTENCES = ["Always, the robot is safe.",
             "If a part is available, eventually the part is picked.",
             "Eventually, the part is placed.",
             "If a part is available, the part is picked before the part is placed."]


@pytest.fixture(scope="module")
def clf():
    return BSIClassifier(global_candidates=["safe"], subtasks=["a", "b"],
                         conditions={"a": "a_ok"}).fit(X, Y)


@pytest.fixture(scope="module")
def report(clf):
    return explain(clf, X, Y, descriptions=DESC, top_k=3, title="Pick & place <test>")


def test_map_and_sentences(clf, report):
    assert clf.map_specification_ == MAP
    assert isinstance(report, SpecificationReport)
    assert report.specification == MAP
    assert report.ltl == "G(safe) & (a_ok -> F(a)) & F(b) & (a_ok -> (!b U a))"
    assert report.ltl_latex == MAP.to_ltl(latex=True)
    assert list(report.clauses.index) == CLAUSES
    assert list(report.clauses["ltl"]) == CLAUSE_LTL
    assert list(report.clauses["kind"]) == ["global", "eventual", "eventual", "order"]
    assert report.sentences == SENTENCES
    marg = clf.posterior_.clause_marginals()
    expected = [marg.to_dict()[k] for k in CLAUSES]
    np.testing.assert_allclose(report.clauses["inclusion_probability"], expected)
    assert report.order_edges == [("a", "b")]


def test_posterior_summary(clf, report):
    post = clf.posterior_
    assert report.n_unique_specifications == len(post)
    assert report.entropy == pytest.approx(post.entropy())
    assert report.map_probability == pytest.approx(post.probabilities[0])
    assert list(report.top.index) == [1, 2, 3]
    np.testing.assert_allclose(report.top["probability"], post.probabilities[:3])
    assert list(report.top["ltl"]) == [s.to_ltl() for s, _ in post.top(3)]
    assert report.top["difference"].iloc[0] == ""
    for (spec, _), diff in zip(post.top(3)[1:], report.top["difference"].iloc[1:]):
        n_changes = len(spec.clauses() ^ MAP.clauses())
        assert diff.count("+ ") + diff.count("- ") == n_changes > 0
    assert report.inference["method"] == "exact"


def test_violations_and_states(clf, report):
    assert report.demo_names == [str(i) for i in range(len(X))]
    np.testing.assert_array_equal(report.predicted_acceptable, clf.predict(X) == 1)
    assert report.violations == {
        "8": [("G", "safe")],
        "9": [("U", "a", "b")],
        "10": [("F", "a"), ("F", "b"), ("U", "a", "b")],
        "11": [("F", "b")],
    }
    for name, keys in report.violations.items():
        assert keys == violated_clauses(MAP, X[int(name)])
    states = report.clause_states
    assert states.shape == (4, len(X))
    # demonstration 3: a part unavailable -> a's eventual and the order are vacuous
    assert list(states["3"]) == [1, 2, 1, 2]
    assert list(states["10"]) == [1, 0, 0, 0]
    np.testing.assert_array_equal(report.map_satisfied, Y == 1)


def test_labels_confusion_and_f1(clf):
    # two demonstrations labelled against the MAP: one false negative, one false positive
    Xt = [POSITIVES[0], POSITIVES[1], NEGATIVES[0], NEGATIVES[1]]
    yt = [1, 0, 1, 0]
    rep = explain(clf, Xt, yt, demo_names=["p0", "p1", "n0", "n1"])
    assert rep.confusion_matrix.to_numpy().tolist() == [[1, 1], [1, 1]]
    assert rep.f1 == pytest.approx(0.5)
    assert rep.f1_weighted == pytest.approx(0.5)
    assert list(rep.violations) == ["n0", "n1"]
    perfect = explain(clf, X, Y)
    assert perfect.confusion_matrix.to_numpy().tolist() == [[8, 0], [0, 4]]
    assert perfect.f1 == perfect.f1_weighted == perfect.vote_f1_weighted == 1.0


def test_bad_arguments(clf):
    with pytest.raises(ValueError, match="'nope' is not a proposition"):
        explain(clf, descriptions={"nope": "x"})
    with pytest.raises(ValueError, match="y was given without X"):
        explain(clf, y=Y)
    with pytest.raises(ValueError, match=r"y\[1\] = 7 is not one of the classifier's classes"):
        explain(clf, X[:2], [1, 7])
    with pytest.raises(ValueError, match="one label per demonstration"):
        explain(clf, X[:2], [1])
    with pytest.raises(ValueError, match="demo_names has 1 entries for 2"):
        explain(clf, X[:2], demo_names=["x"])
    with pytest.raises(ValueError, match="top_k"):
        explain(clf, top_k=0)
    with pytest.raises(ValueError, match="propositions"):
        explain(clf, [np.zeros((3, 2), dtype=bool)])
    from sklearn.exceptions import NotFittedError
    with pytest.raises(NotFittedError):
        explain(BSIClassifier())


# ---------------------------------------------------------------------------- rendering
class _Balanced(HTMLParser):
    VOID = {"meta", "img", "br", "hr", "link", "input"}

    def __init__(self):
        super().__init__()
        self.stack, self.errors = [], []

    def handle_starttag(self, tag, attrs):
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        pass  # <img ... />: nothing to balance

    def handle_endtag(self, tag):
        if not self.stack or self.stack.pop() != tag:
            self.errors.append(tag)


def check_png(data):
    assert data[:8] == PNG_SIGNATURE
    assert len(data) > 2048
    # IHDR: width and height are positive
    width, height = int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
    assert width > 100 and height > 100


def test_html_well_formed_and_complete(report, tmp_path):
    path = report.to_html(tmp_path / "sub" / "report.html")
    assert path.exists()
    text = path.read_text(encoding="utf-8")
    parser = _Balanced()
    parser.feed(text)
    parser.close()
    assert not parser.errors and not parser.stack
    root = ET.fromstring(text.split("\n", 1)[1])  # XHTML-compatible after the doctype
    flat = " ".join("".join(root.itertext()).split())
    for ltl, sentence in zip(CLAUSE_LTL, SENTENCES):
        assert ltl in flat
        assert sentence in flat
    assert "Pick & place <test>" in flat  # escaped in the source, restored by the parser
    assert "<test>" not in text
    images = [el.get("src") for el in root.iter("img")]
    assert len(images) == 4  # marginals, DAG, heatmap, confusion matrix
    for src in images:
        assert src.startswith("data:image/png;base64,")
        check_png(base64.b64decode(src.split(",", 1)[1]))
    assert "http://" not in text and "https://" not in text  # self-contained
    formula = [el for el in root.iter("p") if el.get("class") == "formula"]
    assert ["".join(el.itertext()) for el in formula] == [
        "□(safe) ∧ (a_ok → ◇(a)) ∧ ◇(b) ∧ (a_ok → (¬b U a))"]
    assert "\\mathbf" not in text and "language-latex" not in text


def test_html_escapes_descriptions(clf, tmp_path):
    evil = {"a": "<script>alert('x')</script> & \"quotes\"", "b": "b's *bold* | pipe"}
    rep = explain(clf, X[:3], descriptions=evil)
    text = rep.to_html(tmp_path / "r.html").read_text()
    assert "<script>" not in text
    root = ET.fromstring(text.split("\n", 1)[1])
    assert "<script>alert('x')</script> & \"quotes\"" in "".join(root.itertext())
    md = rep.to_markdown(tmp_path / "md").read_text()
    assert "<script>" not in md
    assert r"b's \*bold\* \| pipe" in md
    assert rep._repr_html_().count("<script>") == 0


def test_markdown_and_figures(report, tmp_path):
    path = report.to_markdown(tmp_path / "md")
    assert path == tmp_path / "md" / "report.md"
    md = path.read_text(encoding="utf-8")
    assert md.startswith("# Pick & place \\<test\\>\n")
    for ltl, sentence in zip(CLAUSE_LTL, SENTENCES):
        assert f"`{ltl}`" in md
        assert sentence in md
    assert "```text\nG(safe) & (a_ok -> F(a)) & F(b) & (a_ok -> (!b U a))\n```" in md
    # The formula in temporal-logic symbols, no raw LaTeX (readable in any viewer, offline).
    assert "> **□(safe) ∧ (a\\_ok → ◇(a)) ∧ ◇(b) ∧ (a\\_ok → (¬b U a))**" in md
    assert "\\mathbf" not in md and "$$" not in md
    linked = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md)
    assert sorted(linked) == ["clause_marginals.png", "confusion_matrix.png", "order_dag.png",
                              "satisfaction.png"]
    for name in linked:
        check_png((tmp_path / "md" / name).read_bytes())
    # Every likely formula rejects it and misclassifies none of the 12 training demonstrations:
    # the learned flip rate (0 + 1) / (12 + 2) is its probability of being acceptable.
    assert "| 10 | 0.071 | unacceptable |" in md
    assert "| acceptable | 8 | 0 |" in md
    assert "entropy" in md and f"{report.n_unique_specifications} unique specifications" in md


def test_report_without_demonstrations(clf, tmp_path):
    rep = explain(clf)
    assert rep.clause_states is None and rep.violations is None and rep.f1 is None
    assert sorted(rep.figures()) == ["clause_marginals", "order_dag"]
    html = rep._repr_html_()
    for ltl in CLAUSE_LTL:
        assert ltl.replace(">", "&gt;") in html
    for sentence in ["Always, safe holds.", "If a_ok holds, eventually a holds."]:
        assert sentence in html
    md = rep.to_markdown(tmp_path).read_text()
    assert "## Demonstrations" not in md and "## Agreement with the labels" not in md


def test_true_specification_report(tmp_path):
    Xs = [np.array([[1, 0], [0, 1]]), np.array([[0, 0], [1, 1]])]
    clf = BSIClassifier(global_candidates=[], subtasks=[]).fit(Xs)
    rep = explain(clf, Xs)
    assert rep.ltl == "true" and rep.sentences == [] and rep.order_edges == []
    assert rep.figures() == {}
    assert rep.violations == {}
    text = rep.to_html(tmp_path / "r.html").read_text()
    ET.fromstring(text.split("\n", 1)[1])
    assert "accepts every demonstration" in text
    assert "no ordering constraints" in rep.to_markdown(tmp_path).read_text()


def test_rejected_by_vote_only(tmp_path):
    # The MAP holds, but under half of the posterior mass does: the table says so.
    Xs = [np.array([[1, 1, 0]]), np.array([[0, 1, 1], [0, 0, 1], [1, 0, 1]]),
          np.array([[0, 1, 1]]), np.array([[0, 0, 0], [0, 0, 0], [0, 1, 0]])]
    clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], p_global=0.3,
                        p_eventual=0.3, likelihood="cb").fit(Xs, [1, 1, 1, 0])
    rep = explain(clf, [np.array([[0, 1, 0]])])
    assert rep.ltl == "F(1) & (!2 U 1)"
    assert rep.map_probability < 0.5
    assert rep.map_satisfied.tolist() == [True]
    assert rep.predicted_acceptable.tolist() == [False]
    assert rep.violations == {"0": []}
    md = rep.to_markdown(tmp_path).read_text()
    assert "none: it satisfies the MAP specification, but the posterior as a whole" in md
    assert "| P(acceptable) |" in md and rep.proba_name == "P(acceptable)"
    # The paper's vote is named for what it is.
    vote = explain(clf.set_params(vote="satisfaction"), [np.array([[0, 1, 0]])])
    assert vote.proba_name == "posterior mass satisfied"
    assert "posterior mass satisfied" in vote.to_markdown(tmp_path / "vote").read_text()


def test_verdicts_come_from_the_classifier():
    # explain restates no decision rule: its verdicts and probabilities are the classifier's.
    class Strict(BSIClassifier):
        def predict_proba(self, X):
            return np.tile([0.3, 0.7], (len(X), 1))

        def predict(self, X):
            return np.full(len(X), self.classes_[0])

    clf = Strict(global_candidates=["safe"], subtasks=["a", "b"],
                 conditions={"a": "a_ok"}).fit(X, Y)
    rep = explain(clf, X, Y)
    np.testing.assert_array_equal(rep.proba, np.full(len(X), 0.7))
    assert not rep.predicted_acceptable.any()
    assert set(rep.violations) == {str(i) for i in range(len(X))}
    assert rep.vote_f1_weighted == pytest.approx(
        f1_score(Y == 1, np.zeros(len(X), bool), average="weighted", labels=[True, False],
                 zero_division=0.0))


def test_layered_layout():
    pos = layered_layout(["a", "b", "c", "d", "e"],
                         [("a", "b"), ("a", "c"), ("b", "d"), ("c", "d"), ("e", "d")])
    layers = {v: p[0] for v, p in pos.items()}
    assert layers == {"a": 0, "e": 0, "b": 1, "c": 1, "d": 2}
    assert sorted(p[1] for v, p in pos.items() if layers[v] == 1) == [-0.5, 0.5]
    assert len(set(pos.values())) == 5


def test_mcmc_report_states_the_chains_agreement():
    clf = BSIClassifier(global_candidates=["safe"], subtasks=["a", "b"],
                        conditions={"a": "a_ok"}, inference="mcmc", n_samples=2000,
                        random_state=0).fit(X, Y)
    rep = explain(clf, X, Y)
    missed = clf.mcmc_diagnostics_["max_missed_mass"]
    assert rep.inference["max_missed_mass"] == pytest.approx(missed) and missed < 0.05
    assert (f"Posterior mass the least thorough MCMC chain never reached: {missed:.3f}"
            in rep.markdown())


def test_a_posterior_reported_by_its_samples_says_so():
    # 40 propositions true throughout: their G clauses are undetermined, each at its prior
    # inclusion 0.2, and the posterior is too diffuse to list (tests/inference/
    # test_mcmc_diffuse.py). The report gives the chains' agreement on clause inclusions, not
    # the missed mass, which weighs states exactly.
    rng = np.random.default_rng(0)
    Xd = [np.ones((3, 41), dtype=int) for _ in range(30)]
    for x in Xd:
        x[:, 40] = rng.integers(0, 2, 3)
    yd = np.array([1, 0] * 15)
    clf = BSIClassifier(likelihood="calibrated", global_candidates=list(range(40)),
                        subtasks=[], conditions={}, p_global=0.2, inference="mcmc",
                        n_samples=500, random_state=0).fit(Xd, yd)
    assert clf.mcmc_diagnostics_["sampled"]
    rep = explain(clf, Xd, yd)
    assert rep.inference["max_missed_mass"] is None
    assert rep.inference["inclusion_rhat"] == pytest.approx(
        clf.mcmc_diagnostics_["inclusion_rhat"])
    text = rep.markdown()
    assert "reported by the MCMC samples" in text and "never reached" not in text
    # The MAP is the most probable formula (the empty one), at its share of the samples.
    post = clf.posterior_
    assert rep.specification == post.map_specification and rep.ltl == "true"
    assert rep.map_probability == post.probabilities[post.map_index]
    assert (f"The most probable specification (share of the samples "
            f"{rep.map_probability:.3f}: the posterior is too diffuse to list") in text


def test_report_files_get_the_umask_mode(report, tmp_path):
    # Issue 21: report files were written with mode 0600 (mkstemp's), not the umask's.
    import os

    old = os.umask(0o022)
    try:
        html = report.to_html(tmp_path / "r.html")
        md = report.to_markdown(tmp_path / "md")
    finally:
        os.umask(old)
    files = [html, *md.parent.iterdir()]
    assert {f.stat().st_mode & 0o777 for f in files} == {0o644}
