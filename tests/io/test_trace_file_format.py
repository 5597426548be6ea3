"""The .trace format (samples2LTL / Scarlet): reading, writing, malformed files."""

import io

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn.io import TraceFile, load_trace_file, read_trace_file, write_trace_file
from bsi_sklearn.ltl import parse_ltl

SAMPLES2LTL = """\
1,0;1,1;1,0
1,1
---
0,1;1,1
0,0;0,0;0,0
---
G,F,!,U,&,|,->,X
---
1
---
G(x0)
"""

SCARLET = """\
1,0,0;0,1,0
0,0,1;1,0,0;0,1,0
---
0,1,0;1,0,0
---
F,G,X,!,&,|
---
a,b,c"""


def write(tmp_path, text, name="demo.trace"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_reads_samples2ltl_layout(tmp_path):
    tf = read_trace_file(write(tmp_path, SAMPLES2LTL))
    assert isinstance(tf, TraceFile)
    assert tf.feature_names == ["x0", "x1"] and tf.n_props == 2
    assert tf.operators == ("G", "F", "!", "U", "&", "|", "->", "X")
    assert tf.depth == 1 and tf.alphabet is None
    assert tf.target == parse_ltl("G(x0)") and tf.target_source == "file"
    np.testing.assert_array_equal(tf.positives[0], [[1, 0], [1, 1], [1, 0]])
    np.testing.assert_array_equal(tf.negatives[1], np.zeros((3, 2)))
    assert tf.positives[0].dtype == bool
    np.testing.assert_array_equal(tf.y, [1, 1, 0, 0])


def test_load_trace_file_returns_frames_labels_target(tmp_path):
    X, y, target = load_trace_file(write(tmp_path, SAMPLES2LTL))
    assert [x.shape for x in X] == [(3, 2), (1, 2), (2, 2), (3, 2)]
    assert all(list(x.columns) == ["x0", "x1"] for x in X)
    assert all(dt == np.bool_ for x in X for dt in x.dtypes)
    np.testing.assert_array_equal(y, [1, 1, 0, 0])
    np.testing.assert_array_equal(target.evaluate(X), y.astype(bool))


def test_scarlet_alphabet_and_formulas_lookup(tmp_path):
    folder = tmp_path / "TracesFiles"
    folder.mkdir()
    (tmp_path / "formulas.txt").write_text("F(a)\nF(&(a,F(b)))\n")
    tf = read_trace_file(write(folder, SCARLET, "f-02-nw-3-ml-3-0.trace"))
    assert tf.feature_names == ["a", "b", "c"] and tf.alphabet == ("a", "b", "c")
    assert tf.depth is None
    assert tf.target == parse_ltl("F(a & F(b))")
    assert tf.target_source.endswith("formulas.txt:2")
    np.testing.assert_array_equal(tf.target.evaluate(tf.X), [True, True, False])
    assert read_trace_file(folder / "f-02-nw-3-ml-3-0.trace", formulas=None).target is None
    # no such file beside it, or a name without f-NN-: no target
    assert read_trace_file(write(tmp_path, SCARLET, "other.trace")).target is None
    with pytest.raises(ValueError, match="does not start with 'f-NN-'"):
        read_trace_file(tmp_path / "other.trace", formulas=tmp_path / "formulas.txt")
    with pytest.raises(ValueError, match="line 9 of .*which has 2 lines"):
        read_trace_file(write(folder, SCARLET, "f-09-x.trace"))
    (tmp_path / "bad.txt").write_text("F(a)\nF(&(a)\n")
    with pytest.raises(ValueError, match=r"bad.txt, line 2: target formula"):
        read_trace_file(folder / "f-02-nw-3-ml-3-0.trace", formulas=tmp_path / "bad.txt")


def test_accepts_crlf_final_newline_and_empty_negatives(tmp_path):
    text = "1,0;1,1\r\n---\r\n---\r\nG,F\r\n"
    tf = read_trace_file(write(tmp_path, text))
    assert len(tf.positives) == 1 and tf.negatives == [] and tf.operators == ("G", "F")
    assert tf.target is None and tf.depth is None


@pytest.mark.parametrize("text, line, message", [
    ("1,0;1\n---\n0,0\n---\nG", 1, "time step 1 has 1 propositions, expected 2"),
    ("1,0\n---\n0,0,1\n---\nG", 3, "time step 0 has 3 propositions, expected 2"),
    ("1,0;1,2\n---\n0,0\n---\nG", 1, "time step 1, proposition 1 has value '2'"),
    ("1,0;1,x\n---\n0,0\n---\nG", 1, "proposition 1 has value 'x'"),
    ("1,0\n\n---\n0,0\n---\nG", 2, "empty trace"),
    ("1,0;;1,1\n---\n0,0\n---\nG", 1, "time step 1 is empty"),
    ("1,0;1,1;\n---\n0,0\n---\nG", 1, "time step 2 is empty"),
    ("1,0\n---\n0,0\nG", 4, "missing '---' separator"),
    ("1,0\n0,1", 2, "missing '---' separator"),
    ("1,0\n---\n0,0\n---\nG\n---\n-1\n---\nG(x0)", 7, "depth must be >= 0"),
    ("1,0\n---\n0,0\n---\nG\n---\n2\n---\nG(x0", 9, "target formula"),
    ("1,0\n---\n0,0\n---\nG\n---\n2\n---\nG(x7)", 9, r"mentions \['x7'\]"),
    ("1,0\n---\n0,0\n---\nG\n---\na,b,c", 7, "the alphabet has 3 names but"),
    ("1,0\n---\n0,0\n---\nG\n---\na,a", 7, "empty or repeated"),
    ("1,0\n---\n0,0\n---\nG\nF", 6, "operators section must hold exactly one line"),
    ("1,0::1\n---\n0,0\n---\nG", 1, r"the lasso start '1' after '::' must be a step of the "
                                     r"trace, 0 to 0"),
    ("1,0;0,1::x\n---\n0,0\n---\nG", 1, "the lasso start 'x'"),
    ("1,0;0,1::0::1\n---\n0,0\n---\nG", 1, "a second '::'"),
    ("1,0\n---\nhello world\n---\nG", 3,
     r"'hello world' is not a trace: unexpected character\(s\) 'dehlorw'; expected time steps "
     r"separated by ';' and the 0/1 propositions of a step by ','"),
    ("1,0;1,1\n1 0;1 1\n---\n---\nG", 2, r"values separated by whitespace \('1 0'\); expected"),
    ("1,0\n1|0\n---\n---\nG", 2, r"unexpected character\(s\) '\|'; expected time steps"),
    ("1\n0|1\n---\n---\nG", 2, r"unexpected character\(s\) '\|'"),
    ("1,0\n---\n0,0\n---\n---\n1", 5, "operators section must hold exactly one line, found 0"),
    ("1,0\n---\n0,0\n---\nG\n---\n1\n---\n", 8, "target formula section must hold"),
    ("1,0\n---\n0,0\n---\nG\n---\na\n---\nF(a)", 8, "unexpected section after the"),
    ("1,0\n---\n0,0\n---\nG\n---\n1\n---\nF(x0)\n---\nx\n---\n", 12, "too many"),
])
def test_malformed_files_name_file_and_line(tmp_path, text, line, message):
    path = write(tmp_path, text, "bad.trace")
    with pytest.raises(ValueError, match=rf"bad\.trace, line {line}: .*{message}"):
        read_trace_file(path)


def test_file_without_traces(tmp_path):
    with pytest.raises(ValueError, match=r"empty\.trace: the file holds no traces"):
        read_trace_file(write(tmp_path, "---\n---\nG", "empty.trace"))


@pytest.mark.parametrize("layout", ["samples2ltl", "scarlet", "plain"])
def test_write_read_round_trip(tmp_path, layout):
    rng = np.random.default_rng(1)
    X = [rng.random((int(rng.integers(1, 8)), 3)) < 0.5 for _ in range(12)]
    y = rng.integers(0, 2, size=12)
    kwargs = {"samples2ltl": dict(target="F(x0) & G(!x2)"),
              "scarlet": dict(operators=("F", "G", "&"), alphabet=["p", "q", "r"]),
              "plain": {}}[layout]
    path = tmp_path / "round.trace"
    write_trace_file(path, X, y, **kwargs)
    tf = read_trace_file(path)
    order = np.r_[np.flatnonzero(y == 1), np.flatnonzero(y == 0)]
    assert len(tf.positives) + len(tf.negatives) == len(X)
    for got, i in zip(tf.positives + tf.negatives, order):
        np.testing.assert_array_equal(got, X[i])
    np.testing.assert_array_equal(tf.y, y[order])
    if layout == "samples2ltl":
        assert tf.target == parse_ltl("F(x0) & G(!x2)") and tf.depth == 3 and tf.target.depth == 3
    if layout == "scarlet":
        assert tf.feature_names == ["p", "q", "r"] and tf.operators == ("F", "G", "&")
    # writing the read file back gives the same text
    buf = io.StringIO()
    write_trace_file(buf, tf.X, tf.y, operators=tf.operators, depth=tf.depth,
                     target=tf.target, alphabet=tf.alphabet)
    assert buf.getvalue() == path.read_text()


def test_write_trace_file_rejects_bad_labels():
    X = [np.ones((2, 2))]
    with pytest.raises(ValueError, match="one label per demonstration"):
        write_trace_file(io.StringIO(), X, [1, 0])
    with pytest.raises(ValueError, match="0/1"):
        write_trace_file(io.StringIO(), X, [2])
    with pytest.raises(ValueError, match="alphabet has 1 names"):
        write_trace_file(io.StringIO(), X, [1], alphabet=["a"])
    with pytest.raises(ValueError, match="target must be"):
        write_trace_file(io.StringIO(), X, [1], target=3)
    with pytest.raises(ValueError, match="demonstration 0"):
        write_trace_file(io.StringIO(), [pd.DataFrame({"a": [0.5]})], [1])


# ------------------------------------------------------------------ Scarlet's formulas lines
SCARLET_PQ = "1,0;0,0\n0,0\n---\n1,1;0,1\n---\nF,G,!,&,|\n---\np,q"


def test_scarlet_formulas_line_with_alphabet_and_lengths(tmp_path):
    # Issue 21: Scarlet's RQ1 folders write 'formula;alphabet;lengths' on a formulas.txt line.
    (tmp_path / "formulas.txt").write_text("G(!(p));p,q;8,10,12\nG(->(q, G(!(p))));p,q;8\n")
    tf = read_trace_file(write(tmp_path, SCARLET_PQ, "f-01-nw-2.trace"))
    assert tf.target == parse_ltl("G(!p)") and tf.lengths == (8, 10, 12)
    assert tf.feature_names == ["p", "q"] and tf.target_source.endswith("formulas.txt:1")
    np.testing.assert_array_equal(tf.target.evaluate(tf.X), [False, True, False])
    # without an alphabet section, the formulas line names the columns
    no_alphabet = SCARLET_PQ.rsplit("\n---\n", 1)[0]
    tf = read_trace_file(write(tmp_path, no_alphabet, "f-02-nw-2.trace"))
    assert tf.feature_names == ["p", "q"] and tf.alphabet is None and tf.lengths == (8,)


@pytest.mark.parametrize("line, message", [
    ("G(!(p));p,q;8;9", ".*found 4 fields"),
    ("G(!(p));p,p;8", "alphabet 'p,p' has empty or repeated names"),
    ("G(!(r));p,q;8", r"the formula mentions \['r'\], which are not in its alphabet"),
    ("G(!(p));p,q;8,x", "trace lengths '8,x' are not positive integers"),
    ("G(!(p);p,q;8", "target formula"),
])
def test_bad_scarlet_formulas_lines_name_the_line(tmp_path, line, message):
    (tmp_path / "formulas.txt").write_text(f"F(p)\n{line}\n")
    with pytest.raises(ValueError, match=rf"formulas.txt, line 2: {message}"):
        read_trace_file(write(tmp_path, SCARLET_PQ, "f-02-x.trace"))


def test_scarlet_alphabet_must_be_carried_by_the_file(tmp_path):
    (tmp_path / "formulas.txt").write_text("F(a);a,b,c;8\nF(p);p,r;8\n")
    with pytest.raises(ValueError, match=r"f-01-x.trace: the target's alphabet "
                                         r"\['a', 'b', 'c'\] on .*formulas.txt:1 has "
                                         r"\['a', 'b', 'c'\], which the file's alphabet "
                                         r"\['p', 'q'\] does not carry"):
        read_trace_file(write(tmp_path, SCARLET_PQ, "f-01-x.trace"))
    with pytest.raises(ValueError, match=r"formulas.txt:2 has \['r'\], which"):
        read_trace_file(write(tmp_path, SCARLET_PQ, "f-02-x.trace"))
    no_alphabet = SCARLET_PQ.rsplit("\n---\n", 1)[0]
    with pytest.raises(ValueError, match=r"names 3 propositions .* but the traces have 2 "
                                         r"and the file has no alphabet line"):
        read_trace_file(write(tmp_path, no_alphabet, "f-01-y.trace"))


SCARLET_ABCD = ("1,0,0,0;0,1,0,0;0,0,0,1\n0,0,0,1;1,0,0,0\n---\n0,0,0,1;0,1,0,0\n---\n"
                "G,F,X,!,&,|\n---\na,b,c,d")


def test_scarlet_target_alphabet_may_be_a_subset_of_the_files(tmp_path):
    # Issue 28: Scarlet's Varying_size folder publishes 'F(...);a,b,c' for traces over
    # a,b,c,d: the formula's alphabet, not the file's.
    (tmp_path / "formulas.txt").write_text("&(F(a),F(b));a,b,c\nF(a);c,b,a;8\n")
    tf = read_trace_file(write(tmp_path, SCARLET_ABCD, "f-01-nw-3-ml-3-0.trace"))
    assert tf.feature_names == ["a", "b", "c", "d"] and tf.alphabet == ("a", "b", "c", "d")
    assert tf.target_alphabet == ("a", "b", "c") and tf.n_props == 4
    assert tf.target == parse_ltl("F(a) & F(b)")
    np.testing.assert_array_equal(tf.target.evaluate(tf.X), [True, False, False])
    # the formula's alphabet is a set of letters: its order does not rename columns
    tf = read_trace_file(write(tmp_path, SCARLET_ABCD, "f-02-nw-3-ml-3-0.trace"))
    assert tf.feature_names == ["a", "b", "c", "d"] and tf.target_alphabet == ("c", "b", "a")
    assert tf.lengths == (8,)
    # a file without a formulas.txt alphabet records none
    (tmp_path / "formulas.txt").write_text("F(a)\n")
    assert read_trace_file(tmp_path / "f-01-nw-3-ml-3-0.trace").target_alphabet is None


def test_scarlet_target_alphabet_letters_the_formula_needs(tmp_path):
    # the formula may only mention letters of its own alphabet, which the file must carry
    (tmp_path / "formulas.txt").write_text("F(d);a,b,c\nF(e)\n")
    with pytest.raises(ValueError, match=r"formulas.txt, line 1: the formula mentions "
                                         r"\['d'\], which are not in its alphabet"):
        read_trace_file(write(tmp_path, SCARLET_ABCD, "f-01-x.trace"))
    with pytest.raises(ValueError, match=r"the target .*formulas.txt:2 mentions \['e'\], "
                                         r"which are not among the propositions"):
        read_trace_file(write(tmp_path, SCARLET_ABCD, "f-02-x.trace"))


# ------------------------------------------------------------------ samples2LTL lasso traces
def test_lasso_traces_are_read_with_their_loop_start(tmp_path):
    text = "1,1;1,0;0,1::1\n1,0\n---\n0,1;1,1::0\n---\nG,F\n---\n1\n---\nF(x0)"
    tf = read_trace_file(write(tmp_path, text))
    assert tf.loop_starts == (1, None, 0)
    assert [t.shape for t in tf.positives + tf.negatives] == [(3, 2), (1, 2), (2, 2)]
    X, y, _ = load_trace_file(tmp_path / "demo.trace")
    assert [len(x) for x in X] == [3, 1, 2]


def _brute_force(spec, trace, names):
    """The template's clauses read on an infinite word given as a long finite prefix."""
    col = {n: trace[:, k] for k, n in enumerate(names)}
    cond = spec.conditions
    if not all(col[p].all() for p in spec.globals):
        return False
    for w in spec.eventuals:
        if (w not in cond or col[cond[w]][0]) and not col[w].any():
            return False
    for a, b in spec.orders:
        if a in cond and not col[cond[a]][0]:
            continue
        hits = np.flatnonzero(col[a])
        if not len(hits) or col[b][:hits[0]].any():
            return False
    return True


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from bsi_sklearn import Specification  # noqa: E402

LASSO_NAMES = ["a", "b", "c"]
SPECS = st.builds(
    lambda g, e, o, c: Specification(globals=g, eventuals=e, orders=o,
                                     conditions={"a": "c"} if c else None),
    st.lists(st.sampled_from(LASSO_NAMES), max_size=2, unique=True),
    st.lists(st.sampled_from(LASSO_NAMES), max_size=2, unique=True),
    st.sampled_from([[], [("a", "b")], [("b", "a")], [("a", "c")]]),
    st.booleans())


@settings(max_examples=200, deadline=None)
@given(spec=SPECS, steps=st.lists(st.lists(st.booleans(), min_size=3, max_size=3), min_size=1,
                                  max_size=6), data=st.data())
def test_a_lasso_read_as_u_then_v_is_exact_for_the_template(spec, steps, data):
    # The finite reading of u v (last state repeating) against the lasso u v v v ... unrolled.
    start = data.draw(st.integers(0, len(steps) - 1))
    trace = np.array(steps, dtype=bool)
    unrolled = np.concatenate([trace[:start]] + [trace[start:]] * 8)
    assert spec.satisfied_by(trace, feature_names=LASSO_NAMES) == _brute_force(
        spec, unrolled, LASSO_NAMES)
