"""The pattern library against independent LTLf evaluators, on every short trace.

Each template's kernel is checked on **all** traces of length 1..4 over its slots' propositions
(exhaustive) against (a) a brute-force recursive LTLf evaluator over the template's formula
text, parsed here by a tiny parser (the project's ``ltl`` reader has no weak next), and (b)
flloat, which reads the formula text as written.
"""

import itertools
import re

import numpy as np
import pytest
from _reference import all_traces, stack_traces
from hypothesis import given, settings
from hypothesis import strategies as st

from bsi_sklearn.model.patterns import (
    FAMILIES,
    TEMPLATES,
    get_template,
    instance_ltlf,
    instance_text,
    instantiate,
    pattern_truth,
)

# ----------------------------------------------------------- a tiny LTLf parser and evaluator
_TOK = re.compile(r"\s*(<->|->|WX|[()!&|]|[A-Za-z_]+)")
_UNARY = {"!", "X", "WX", "F", "G"}


def _tokens(text):
    out, pos = [], 0
    while pos < len(text.rstrip()):
        m = _TOK.match(text, pos)
        assert m, text[pos:]
        out.append(m.group(1))
        pos = m.end()
    return out


def _parse(text):
    toks = _tokens(text)
    pos = [0]

    def peek():
        return toks[pos[0]] if pos[0] < len(toks) else None

    def take():
        pos[0] += 1
        return toks[pos[0] - 1]

    def equivalence():  # lowest
        left = implication()
        while peek() == "<->":
            take()
            left = ("<->", left, implication())
        return left

    def implication():
        left = disjunction()
        if peek() == "->":
            take()
            return ("->", left, disjunction())
        return left

    def disjunction():
        left = conjunction()
        while peek() == "|":
            take()
            left = ("|", left, conjunction())
        return left

    def conjunction():
        left = until()
        while peek() == "&":
            take()
            left = ("&", left, until())
        return left

    def until():
        left = unary()
        if peek() in ("U", "R"):
            op = take()
            return (op, left, until())
        return left

    def unary():
        tok = take()
        if tok in _UNARY:
            return (tok, unary())
        if tok == "(":
            inner = equivalence()
            assert take() == ")"
            return inner
        return ("atom", tok)

    tree = equivalence()
    assert pos[0] == len(toks), text
    return tree


def _holds(f, trace, t):
    """LTLf truth of ``f`` at step ``t`` of ``trace`` (a list of sets of atoms), by definition."""
    n = len(trace)
    op = f[0]
    if op == "atom":
        return {"true": True, "false": False}.get(f[1], f[1] in trace[t])
    if op == "!":
        return not _holds(f[1], trace, t)
    if op == "&":
        return _holds(f[1], trace, t) and _holds(f[2], trace, t)
    if op == "|":
        return _holds(f[1], trace, t) or _holds(f[2], trace, t)
    if op == "->":
        return not _holds(f[1], trace, t) or _holds(f[2], trace, t)
    if op == "<->":
        return _holds(f[1], trace, t) == _holds(f[2], trace, t)
    if op == "X":
        return t + 1 < n and _holds(f[1], trace, t + 1)
    if op == "WX":
        return t + 1 >= n or _holds(f[1], trace, t + 1)
    if op == "F":
        return any(_holds(f[1], trace, j) for j in range(t, n))
    if op == "G":
        return all(_holds(f[1], trace, j) for j in range(t, n))
    if op == "U":
        return any(_holds(f[2], trace, j) and all(_holds(f[1], trace, k) for k in range(t, j))
                   for j in range(t, n))
    if op == "R":
        return not _holds(("U", ("!", f[1]), ("!", f[2])), trace, t)
    raise AssertionError(op)


# ----------------------------------------------------------- all traces up to length 4


def _as_sets(trace, slots):
    return [{s for s, v in zip(slots, row) if v} for row in trace]


@pytest.mark.parametrize("name", list(TEMPLATES))
def test_truth_matches_brute_force_and_flloat_on_every_short_trace(name):
    from flloat.parser.ltlf import LTLfParser

    t = TEMPLATES[name]
    slots = t.slots
    traces = list(all_traces(len(slots)))
    data, offsets = stack_traces(traces)
    got = pattern_truth(name, data, offsets, [list(range(len(slots)))])[:, 0]
    tree = _parse(t.formula)
    flloat_formula = LTLfParser()(t.formula)
    assert flloat_formula.find_labels() == set(slots)
    for tr, g in zip(traces, got):
        sets = _as_sets(tr, slots)
        brute = _holds(tree, sets, 0)
        fl = flloat_formula.truth([{s: (s in st) for s in slots} for st in sets], 0)
        assert bool(g) == brute == fl, (name, sets)


@pytest.mark.parametrize("name", [n for n, t in TEMPLATES.items() if len(t.slots) == 2])
def test_columns_are_read_where_they_are_with_a_third_proposition(name):
    # 3 propositions, slots on columns (2, 0); the other column is noise.
    t = TEMPLATES[name]
    traces = list(all_traces(3, max_len=3))
    data, offsets = stack_traces(traces)
    got = pattern_truth(name, data, offsets, [[2, 0], [0, 2]])
    tree = _parse(t.formula)
    for tr, g in zip(traces, got):
        fwd = [{s for s, c in zip(t.slots, (2, 0)) if row[c]} for row in tr]
        bwd = [{s for s, c in zip(t.slots, (0, 2)) if row[c]} for row in tr]
        assert (bool(g[0]), bool(g[1])) == (_holds(tree, fwd, 0), _holds(tree, bwd, 0))


def test_longer_random_traces_match_brute_force():
    rng = np.random.default_rng(0)
    traces = [tuple(map(tuple, rng.integers(0, 2, (rng.integers(5, 12), 2))))
              for _ in range(60)]
    data, offsets = stack_traces(traces)
    for name, t in TEMPLATES.items():
        got = pattern_truth(name, data, offsets, [list(range(len(t.slots)))])[:, 0]
        tree = _parse(t.formula)
        want = [_holds(tree, _as_sets(tr, t.slots), 0) for tr in traces]
        assert got.astype(bool).tolist() == want, name


def test_every_template_has_slots_formula_sentence_and_family():
    assert len(TEMPLATES) == 24
    for name, t in TEMPLATES.items():
        assert t.name == name and t.slots and t.sentence.strip() and t.code >= 0
        assert t.family in FAMILIES and t.family != "user"
        assert set(re.findall(r"\b[a-z]\b", t.formula)) == set(t.slots)


def test_unknown_template_is_named_and_the_known_listed():
    with pytest.raises(ValueError, match=r"unknown template 'Respons'; the known templates "
                                         r"are: Existence, .*Response, .*Choice"
                                         r".*G\(x -> F\(y\)\)"):
        get_template("Respons")


def test_instantiate_lists_ordered_pairs_or_sets():
    assert len(instantiate("Response", range(40))) == 1560
    assert instantiate("Existence", ["x", "y"]) == [("x",), ("y",)]
    assert instantiate("CoExistence", ["x", "y", "z"]) == [("x", "y"), ("x", "z"), ("y", "z")]


def test_empty_demonstration_is_refused():
    data = np.zeros((2, 2), dtype=np.uint8)
    with pytest.raises(ValueError, match="demonstration 1 has no step"):
        pattern_truth("Response", data, np.array([0, 2, 2, 2]), [[0, 1]])


def test_no_instances_gives_an_empty_column_set():
    out = pattern_truth("Response", np.zeros((3, 2)), np.array([0, 3]), np.zeros((0, 2)))
    assert out.shape == (1, 0)


# ----------------------------------------------------------- the generic evaluator
@pytest.mark.parametrize("name", list(TEMPLATES))
def test_the_catalogue_formula_read_as_a_user_template_gives_the_kernel_truth(name):
    # Two independent implementations of one definition: the hand recurrence and the
    # formula's program (every step, every subformula).
    t = TEMPLATES[name]
    traces = list(all_traces(3, max_len=4))
    data, offsets = stack_traces(traces)
    cols = [list(c) for c in itertools.permutations(range(3), len(t.slots))]
    user = get_template(f"({t.formula})")  # in parentheses: never a name, read as LTLf
    assert user.code == -1 and user.family == "user"
    order = [user.slots.index(s) for s in t.slots]  # the formula's slots in its own order
    user_cols = [[c[t.slots.index(s)] for s in user.slots] for c in cols]
    assert sorted(order) == list(range(len(t.slots)))
    np.testing.assert_array_equal(pattern_truth(user, data, offsets, user_cols),
                                  pattern_truth(name, data, offsets, cols))


_ATOMS = st.sampled_from(["x", "y", "z", "true", "false"])


def _render(tree):
    if isinstance(tree, str):
        return tree
    op, *kids = tree
    if len(kids) == 1:
        return f"{op}({_render(kids[0])})"
    return f"({_render(kids[0])} {op} {_render(kids[1])})"


_FORMULAS = st.recursive(
    _ATOMS,
    lambda inner: st.one_of(
        st.tuples(st.sampled_from(["!", "X", "WX", "F", "G"]), inner),
        st.tuples(st.sampled_from(["&", "|", "->", "<->", "U", "R"]), inner, inner)),
    max_leaves=6)


@settings(max_examples=60, deadline=None)
@given(_FORMULAS)
def test_user_templates_against_brute_force_and_flloat_on_every_short_trace(tree):
    from flloat.parser.ltlf import LTLfParser

    text = _render(tree)
    names = [n for n in ("x", "y", "z") if re.search(rf"\b{n}\b", text)]
    if not names:
        with pytest.raises(ValueError, match="has no placeholder"):
            get_template(text)
        return
    t = get_template(text)
    assert sorted(t.slots) == names
    traces = list(all_traces(3, max_len=4))
    data, offsets = stack_traces(traces)
    got = pattern_truth(t, data, offsets, [[("x", "y", "z").index(s) for s in t.slots]])[:, 0]
    want = [_holds(_parse(text), _as_sets(tr, ("x", "y", "z")), 0) for tr in traces]
    assert got.astype(bool).tolist() == want, text
    flloat_formula = LTLfParser()(text)
    sample = traces[:: max(1, len(traces) // 120)]
    for tr in sample:
        sets = _as_sets(tr, ("x", "y", "z"))
        fl = flloat_formula.truth([{s: (s in st_) for s in "xyz"} for st_ in sets], 0)
        assert fl == _holds(_parse(text), sets, 0), (text, sets)


@pytest.mark.parametrize("text, message", [
    ("G(x -> F(y)", r"expected '\)' at position 11 in the template 'G\(x -> F\(y\)', "
                    r"found the end"),
    ("G(x -> )", r"expected a placeholder, a constant, '\(' or a unary operator at position 7 "
                 r"in the template 'G\(x -> \)', found '\)'"),
    ("F(", r"expected a formula at position 2"),
    ("x & & y", r"expected a placeholder, a constant, '\(' or a unary operator at position 4"),
    ("G(x) y", r"expected an operator or the end at position 5"),
    ("G(x -> F(y)) # z", r"unexpected character '#' at position 13"),
    ("F(true)", r"has no placeholder"),
    ("x -> y -> z", r"expected parentheses around one of the -> \(x -> y -> z is "
                    r"ambiguous\); an operator at position 7"),
    ("x <-> y <-> z", r"around one of the <-> \(x <-> y <-> z is ambiguous\)"),
    ("F(a & b & c & d)", r"has 4 placeholders \(a, b, c, d\); at most 3"),
    ("", r"empty"),
])
def test_a_bad_user_template_is_refused_with_its_position(text, message):
    with pytest.raises(ValueError, match=message):
        get_template(text)


def test_a_template_must_be_text():
    with pytest.raises(TypeError, match="a name or an LTLf string, got int"):
        get_template(3)


def test_user_template_instances_and_truth_on_named_columns():
    t = get_template("G(x -> F(y))")
    assert (t.slots, t.symmetric, t.family) == (("x", "y"), False, "user")
    assert instantiate(t, ["p", "q"]) == [("p", "q"), ("q", "p")]
    data = np.array([[1, 0], [0, 1], [1, 0]], dtype=np.uint8)
    np.testing.assert_array_equal(pattern_truth(t, data, np.array([0, 3]), [[0, 1], [1, 0]]),
                                  pattern_truth("Response", data, np.array([0, 3]),
                                                [[0, 1], [1, 0]]))


@pytest.mark.parametrize("bare, bracketed", [
    ("x U y U z", "x U (y U z)"),
    ("x & y | z", "(x & y) | z"),
    ("x | y & z", "x | (y & z)"),
    ("x <-> y -> z", "x <-> (y -> z)"),
    ("x -> y <-> z", "(x -> y) <-> z"),
    ("!x U y", "(!x) U y"),
    ("x & y U z", "x & (y U z)"),
    ("x R y & z", "(x R y) & z"),
    ("x | y <-> z", "(x | y) <-> z"),
    ("X x U G y", "(X(x)) U (G(y))"),
])
def test_precedence_as_flloat_reads_it(bare, bracketed):
    from flloat.parser.ltlf import LTLfParser

    traces = list(all_traces(3, max_len=3))
    data, offsets = stack_traces(traces)
    cols = [[("x", "y", "z").index(s) for s in get_template(bare).slots]]
    np.testing.assert_array_equal(pattern_truth(bare, data, offsets, cols),
                                  pattern_truth(bracketed, data, offsets, cols))
    flloat_formula = LTLfParser()(bare)
    for tr, g in zip(traces, pattern_truth(bare, data, offsets, cols)[:, 0]):
        sets = _as_sets(tr, ("x", "y", "z"))
        assert flloat_formula.truth([{s: (s in st_) for s in "xyz"} for st_ in sets], 0) == bool(g)


def test_the_docs_list_every_template_as_defined_and_their_example_runs():
    import doctest
    from pathlib import Path

    doc = Path(__file__).resolve().parents[1] / "docs" / "patterns.md"
    text = doc.read_text(encoding="utf-8")
    for t in TEMPLATES.values():
        assert f"| `{t.name}` | {', '.join(t.slots)} | `{t.formula}` | {t.sentence} | " \
               f"{t.family} |" in text, t.name
    result = doctest.testfile(str(doc), module_relative=False, verbose=False)
    assert result.attempted >= 4 and result.failed == 0


# ----------------------------------------------------------- instances in the propositions' names
_NAMES = ("order", "pay", "ship")


@pytest.mark.parametrize("name", list(TEMPLATES))
def test_an_instance_formula_is_the_instance_flloat_reads(name):
    # The formula written over the propositions' names (not the slots) has the truth
    # pattern_truth computes for those columns, read by flloat on every trace up to length 3.
    from flloat.parser.ltlf import LTLfParser

    t = TEMPLATES[name]
    names = _NAMES[::-1][: len(t.slots)]  # slots filled out of column order
    cols = [[_NAMES.index(n) for n in names]]
    text = instance_ltlf(name, names)
    assert not set(re.findall(r"\b[a-z]\b", text)), text  # no placeholder left
    formula = LTLfParser()(text)
    traces = list(all_traces(3, max_len=3))
    data, offsets = stack_traces(traces)
    for tr, g in zip(traces, pattern_truth(name, data, offsets, cols)[:, 0]):
        sets = _as_sets(tr, _NAMES)
        assert formula.truth([{n: (n in st_) for n in _NAMES} for st_ in sets], 0) == bool(g)


@pytest.mark.parametrize("name", list(TEMPLATES))
def test_an_instance_reads_in_its_declare_name_and_its_propositions(name):
    t = TEMPLATES[name]
    names = _NAMES[: len(t.slots)]
    text = instance_text(name, names)
    assert text.startswith(f"{name}({', '.join(names)}): ")
    reading = text.split(": ", 1)[1]
    assert not set(re.findall(r"\b[a-z]\b", reading)) & set(t.slots), text
    for n in names:
        assert re.search(rf"\b{n}\b", reading), (text, n)


def test_instance_errors_name_the_slots_and_the_proposition():
    with pytest.raises(ValueError, match=r"'Response' has 2 slots \(a, b\), got 1"):
        instance_ltlf("Response", ["pay"])
    with pytest.raises(ValueError, match=r"proposition 'Pay' cannot be an LTLf2DFA / flloat "
                                         r"atom: atoms are lowercase.*dialect='spot'"):
        instance_ltlf("Response", ["Pay", "ship"])
    with pytest.raises(ValueError, match="dialect must be"):
        instance_ltlf("Response", ["pay", "ship"], dialect="flloat")
    assert instance_text("G(x -> F(y))", ["pay", "ship"]) == "G(pay -> F(ship)) holds"
