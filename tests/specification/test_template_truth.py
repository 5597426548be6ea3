"""The value type's own LTLf evaluator (``templates.step_truth`` / ``holds``) against the model.

``bsi_sklearn.model.patterns.pattern_truth`` (numba kernels, and the compiled program for user
templates) is the reference: the specification layer may not import it, so the two are compared
here, on every trace up to length 4 over 2 and 3 propositions and on random longer traces.
"""


import numpy as np
import pytest
from _reference import all_traces, stack_traces

from bsi_sklearn.model.patterns import TEMPLATES, instantiate, pattern_truth
from bsi_sklearn.specification import Specification
from bsi_sklearn.specification.template_truth import holds, step_truth

_USER = ["G(x -> WX(!x))", "x R y", "(x <-> y) U (x & !y)", "X(x) | WX(false)",
         "G(x -> X(y U z))", "F(x) -> !WX(true)"]




def _padded(traces):
    """(n, T_max, n_props) with each trace's last state repeated, and the lengths."""
    t_max = max(len(tr) for tr in traces)
    cube = np.array([list(tr) + [tr[-1]] * (t_max - len(tr)) for tr in traces], dtype=bool)
    return cube, np.array([len(tr) for tr in traces])


@pytest.mark.parametrize("name", [*TEMPLATES, *_USER])
@pytest.mark.parametrize("n_props", [2, 3])
def test_every_trace_up_to_length_4_matches_pattern_truth(name, n_props):
    traces = list(all_traces(n_props))
    data, offsets = stack_traces(traces)
    instances = instantiate(name, range(n_props))
    expected = pattern_truth(name, data, offsets, instances).astype(bool)
    cube, lengths = _padded(traces)
    for k, cols in enumerate(instances):
        got = step_truth(name, cube[:, :, list(cols)], lengths)[:, 0]
        np.testing.assert_array_equal(got, expected[:, k], err_msg=f"{name}{cols}")


@pytest.mark.parametrize("name", [*TEMPLATES, *_USER])
def test_holds_on_one_trace_at_a_time(name):
    traces = list(all_traces(2, max_len=3))
    data, offsets = stack_traces(traces)
    instances = instantiate(name, range(2))
    expected = pattern_truth(name, data, offsets, instances).astype(bool)
    for i, tr in enumerate(traces):
        arr = np.array(tr)
        for k, cols in enumerate(instances):
            assert holds(name, arr[:, list(cols)]) == expected[i, k], (name, tr, cols)


@pytest.mark.parametrize("name", [*TEMPLATES, *_USER])
def test_random_traces_and_every_step_match_pattern_truth(name):
    rng = np.random.default_rng(sum(map(ord, name)))
    traces = [rng.random((int(rng.integers(1, 12)), 3)) < rng.uniform(0.1, 0.9)
              for _ in range(150)]
    traces[0] = traces[0][:1]  # a length-1 trace among them
    instances = instantiate(name, range(3))
    # the truth at step t is the truth at step 0 of the suffix from t
    suffixes = [tr[t:] for tr in traces for t in range(len(tr))]
    data, offsets = stack_traces(suffixes)
    expected = pattern_truth(name, data, offsets, instances).astype(bool)
    row = 0
    for tr in traces:
        for k, cols in enumerate(instances):
            got = step_truth(name, tr[:, list(cols)])
            np.testing.assert_array_equal(got, expected[row:row + len(tr), k])
        row += len(tr)


def test_padding_by_the_last_state_reads_as_the_last_step():
    trace = np.array([[1, 0], [0, 1], [1, 0]])
    padded = np.concatenate([trace, trace[-1:], trace[-1:]])[None]
    got = step_truth("ChainResponse", padded, lengths=[3])[0]
    np.testing.assert_array_equal(got[:3], step_truth("ChainResponse", trace))
    assert (got[2:] == got[2]).all()


def test_bad_values_are_refused_naming_the_slots():
    with pytest.raises(ValueError, match=r"one column per slot \(a, b\)"):
        step_truth("Response", np.zeros((3, 1)))
    with pytest.raises(ValueError, match="at least one step"):
        step_truth("Response", np.zeros((0, 2)))
    with pytest.raises(ValueError, match="lengths"):
        step_truth("Response", np.zeros((2, 3, 2)), lengths=[4, 1])
    with pytest.raises(ValueError, match="2-D"):
        holds("Response", np.zeros((1, 3, 2)))


@pytest.mark.parametrize("name", [*TEMPLATES, *_USER[:3]])
def test_satisfied_by_reads_the_pattern_clauses_as_pattern_truth(name):
    rng = np.random.default_rng(7)
    traces = [rng.random((int(rng.integers(1, 7)), 3)) < 0.5 for _ in range(60)]
    data, offsets = stack_traces(traces)
    names = ["p", "q", "r"]
    for cols in instantiate(name, range(3))[:3]:
        spec = Specification(globals=[], patterns=[(name, [names[c] for c in cols])])
        expected = pattern_truth(name, data, offsets, [cols])[:, 0].astype(bool)
        got = [spec.satisfied_by(tr, feature_names=names) for tr in traces]
        np.testing.assert_array_equal(got, expected)


def test_satisfied_by_conjoins_the_pattern_clauses_with_the_others():
    spec = Specification(eventuals=["a"], patterns=[("ChainResponse", ("a", "b"))])
    names = ["a", "b"]
    assert spec.satisfied_by(np.array([[1, 0], [0, 1]]), feature_names=names)
    # F(a) holds, but a at the last step has no next step (LTLf's strong next)
    assert not spec.satisfied_by(np.array([[0, 0], [1, 1]]), feature_names=names)
    assert not spec.satisfied_by(np.array([[0, 1]]), feature_names=names)  # no a
    # column indices work as for the other clauses
    assert Specification(patterns=[("Precedence", (0, 1))]).satisfied_by([[1, 0], [0, 1]])
    with pytest.raises(ValueError, match="proposition 'z' is not a column"):
        Specification(patterns=[("Existence", ["z"])]).satisfied_by(
            np.ones((2, 2)), feature_names=names)


def test_clause_keys_and_readable_vacuous_take_pattern_keys():
    spec = Specification(globals=["s"], patterns=[("Response", ("a", "b")),
                                                  ("CoExistence", ("d", "c"))])
    assert spec.clauses() == {("G", "s"), ("P", "Response", ("a", "b")),
                              ("P", "CoExistence", ("c", "d"))}
    assert spec.readable() == "G(s) & CoExistence(c, d) & Response(a, b)"
    assert spec.readable(vacuous=[("P", "Response", ("a", "b"))]) == \
        "G(s) & CoExistence(c, d)  [untested: Response(a, b)]"
    with pytest.raises(ValueError, match=r"\('P', template, propositions\)"):
        spec.readable(vacuous=[("P", "Response", "ab")])
    # a negated column is the literal in the readable text, as in the other clauses
    assert Specification(patterns=[("Response", ("!a", "b"))]).readable() == "Response(!a, b)"
    assert Specification(patterns=[("Response", ("!a", "b"))]).readable(negations=False) == \
        'Response("!a", b)'


def test_jaccard_counts_pattern_clauses():
    from bsi_sklearn.metrics import jaccard_similarity

    truth = Specification(globals=["s"], patterns=[("Response", ("a", "b"))])
    assert jaccard_similarity(Specification(globals=["s"]), truth) == 0.5
    assert jaccard_similarity(Specification(globals=["s"], patterns=[("Response", ("b", "a"))]),
                              truth) == 1 / 3
    assert jaccard_similarity(truth, truth) == 1.0


# ------------------------------------------------------------------ to_ltlf with pattern clauses
def _project_truth(text, names, trace):
    """The project's LTLf reader and evaluator on the whole text (any number of atoms)."""
    from bsi_sklearn.specification.template_truth import _tree_steps
    from bsi_sklearn.specification.templates import parse_ltlf

    arr = np.asarray(trace, dtype=bool)[None]
    atoms = {n: arr[:, :, k] for k, n in enumerate(names)}
    at_end = np.arange(arr.shape[1])[None, :] >= arr.shape[1] - 1
    return bool(_tree_steps(parse_ltlf(text), atoms, at_end)[0, 0])


@pytest.mark.parametrize("name", [*TEMPLATES, *_USER[:3]])
def test_to_ltlf_writes_the_instance_formula_flloat_and_the_project_read_alike(name):
    from bsi_sklearn.specification.templates import get_template

    n = len(get_template(name).slots)
    spec = Specification(globals=["s"], orders=[("a", "b")],
                         patterns=[(name, ["b", "!c", "a"][:n])])
    text = spec.to_ltlf(dialect="ltlf2dfa")
    assert text.startswith("G(s) & (!(b) U (a)) & (")
    names = ["a", "b", "c", "s"]
    rng = np.random.default_rng(11)
    traces = [rng.random((int(rng.integers(1, 6)), 4)) < 0.6 for _ in range(120)]
    traces += [np.array([[0, 0, 0, 1]], dtype=bool), np.ones((1, 4), dtype=bool)]
    flloat = pytest.importorskip("flloat.parser.ltlf")
    formula = flloat.LTLfParser()(text)
    for tr in traces:
        # the column "!c" is the negation of c: give the specification that column too
        full = np.concatenate([tr, ~tr[:, 2:3]], axis=1)
        expected = spec.satisfied_by(full, feature_names=[*names, "!c"])
        assert _project_truth(text, names, tr) == expected, (text, tr.astype(int))
        steps = [{a: bool(v) for a, v in zip(names, row)} for row in tr]
        assert formula.truth(steps, 0) == expected, (text, tr.astype(int))


def test_to_ltlf_spot_writes_the_strong_next_spot_reads_in_both_logics():
    spec = Specification(patterns=[("ChainResponse", ("Fee", "b")),
                                   ("AlternatePrecedence", ("a", "b"))])
    text = spec.to_ltlf(dialect="spot")
    assert text == ('(((!b U a) | G(!b)) & G(b -> !X[!]!((!b U a) | G(!b))))'
                    ' & (G("Fee" -> X[!](b)))')
    try:
        import spot
    except ImportError:
        pytest.skip("Spot is not installed")
    if not hasattr(spot, "from_ltlf"):
        pytest.skip("the spot module here is not Spot's Python binding")
    spot.from_ltlf(spot.formula(text))
