"""Negated columns in the readable texts: no ``!!p``, and the reduced orders mean the same.

Every clause the template can make over the columns ``p, q`` and their negations (``!p, !q``,
and ``!!p, !!q``: the augmenter applied twice) is rendered by :meth:`Specification.readable`,
:func:`unicode_ltl` and :func:`to_ltlf`. Each text is parsed (the project's ``parse_ltl``;
flloat for the export) and evaluated over ``p`` and ``q`` alone on every trace of up to four
steps by a brute-force LTLf evaluator written here, which knows nothing of the project's
semantics. Its truth must equal the project's own truth of the clause on the traces with the
negated columns: ``clause_truth`` (the fit's kernel) and ``Specification.satisfied_by``.
"""

import itertools

import numpy as np
import pytest

from bsi_sklearn import Specification
from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.ltl import (
    And,
    Atom,
    Constant,
    Eventually,
    Globally,
    Implies,
    Not,
    Or,
    Until,
    parse_ltl,
)
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order, clause_truth
from bsi_sklearn.report.wording import clause_specification, unicode_ltl

BASE = ["p", "q"]
COLUMNS = ["p", "q", "!p", "!q", "!!p", "!!q"]


def _column(trace, name):
    """A column of the augmented trace: ``name`` over the base propositions."""
    value = trace[:, BASE.index(name.lstrip("!"))]
    return value if (len(name) - len(name.lstrip("!"))) % 2 == 0 else ~value


def _all_traces(max_len):
    states = [np.array(s, dtype=bool) for s in itertools.product([False, True], repeat=2)]
    return [np.array(steps) for t in range(1, max_len + 1)
            for steps in itertools.product(states, repeat=t)]


TRACES = _all_traces(4)  # 4 + 16 + 64 + 256 traces over p, q
AUGMENTED = [np.stack([_column(tr, c) for c in COLUMNS], axis=1) for tr in TRACES]


def holds(f, trace, t=0):
    """LTLf truth of ``f`` at step ``t`` of the finite ``trace`` (columns ``BASE``)."""
    n = len(trace)
    if isinstance(f, Constant):
        return f.value
    if isinstance(f, Atom):
        return bool(trace[t, BASE.index(f.name)])
    if isinstance(f, Not):
        return not holds(f.operand, trace, t)
    if isinstance(f, And):
        return holds(f.left, trace, t) and holds(f.right, trace, t)
    if isinstance(f, Or):
        return holds(f.left, trace, t) or holds(f.right, trace, t)
    if isinstance(f, Implies):
        return not holds(f.left, trace, t) or holds(f.right, trace, t)
    if isinstance(f, Eventually):
        return any(holds(f.operand, trace, j) for j in range(t, n))
    if isinstance(f, Globally):
        return all(holds(f.operand, trace, j) for j in range(t, n))
    if isinstance(f, Until):
        return any(holds(f.right, trace, j) and all(holds(f.left, trace, k) for k in range(t, j))
                   for j in range(t, n))
    raise AssertionError(f"no rule for {f!r}")


def _keys():
    """Every clause over COLUMNS: (key, conditions)."""
    out = [(("G", x), {}) for x in COLUMNS]
    for w in COLUMNS:
        out += [(("F", w), {} if c is None else {w: c}) for c in [None, *COLUMNS] if c != w]
    for a, b in itertools.permutations(COLUMNS, 2):
        out += [(("U", a, b), {} if c is None else {a: c}) for c in [None, *COLUMNS] if c != a]
    return out


KEYS = _keys()


def _kernel_truth():
    """The project's clause truth of every key of KEYS on AUGMENTED (clause_truth)."""
    n = len(COLUMNS)
    traces = check_traces(AUGMENTED)
    out = {}
    for shift in range(n):  # shift 0: no conditions; else subtask w has condition w + shift
        conds = {} if shift == 0 else {w: (w + shift) % n for w in range(n)}
        roles = resolve_roles(list(range(n)), list(range(n)), conds, n)
        truth = clause_truth(traces, roles)
        cond = {COLUMNS[w]: COLUMNS[c] for w, c in conds.items()}
        for w in range(n):
            if shift == 0:
                out[(("G", COLUMNS[w]), ())] = truth[:, w]
            key = (("F", COLUMNS[w]), tuple(sorted({COLUMNS[w]: cond[COLUMNS[w]]}.items()))
                   if cond else ())
            out[key] = truth[:, clause_index_eventual(w, n)]
            for b in range(n):
                if b != w:
                    key = (("U", COLUMNS[w], COLUMNS[b]),
                           tuple({COLUMNS[w]: cond[COLUMNS[w]]}.items()) if cond else ())
                    out[key] = truth[:, clause_index_order(w, b, n, n)]
    return out


KERNEL = _kernel_truth()


def _project_truth(key, conds):
    truth = KERNEL[(key, tuple(conds.items()))].astype(bool)
    spec = clause_specification(key, conds)
    by_spec = np.array([spec.satisfied_by(x, feature_names=COLUMNS) for x in AUGMENTED])
    np.testing.assert_array_equal(truth, by_spec)  # the kernel and the value type agree
    return truth


def _text_truth(text, traces=TRACES):
    formula = parse_ltl(text)
    assert formula.atoms <= set(BASE), text
    return np.array([holds(formula, tr) for tr in traces])


def _ascii(unicode_text):
    for sym, op in (("□", "G"), ("◇", "F"), ("¬", "!"), ("→", "->"), ("∧", "&"), ("⊤", "true")):
        unicode_text = unicode_text.replace(sym, op)
    return unicode_text


def test_the_kernel_covers_every_clause():
    assert len(KEYS) == 6 + 6 * 6 + 30 * 6
    assert all((k, tuple(c.items())) in KERNEL for k, c in KEYS)


@pytest.mark.parametrize("key, conds", KEYS, ids=lambda v: repr(v))
def test_readable_and_unicode_texts_mean_the_clause(key, conds):
    spec = clause_specification(key, conds)
    expected = _project_truth(key, conds)
    text = spec.readable()
    assert "!!" not in text and '"' not in text
    np.testing.assert_array_equal(_text_truth(text), expected,
                                  err_msg=f"{spec.to_ltl()} -> {text}")
    uni = unicode_ltl(spec)
    assert "¬¬" not in uni and "!" not in uni
    np.testing.assert_array_equal(_text_truth(_ascii(uni)), expected, err_msg=uni)


def test_the_reductions_are_those_of_the_table():
    # (clause over columns, conditions) -> readable text: each rule of bsi_sklearn._literals
    cases = [
        (("U", "p", "!p"), {}, "p"),                    # (!!p U p) = p at the first step
        (("U", "!p", "p"), {}, "!p"),                   # (!p U !p) = !p
        (("U", "!!p", "p"), {}, "F(p)"),                # (!p U p) = F(p)
        (("U", "p", "!!p"), {}, "F(p)"),
        (("U", "a", "!q"), {}, "(q U a)"),              # (!!q U a)
        (("U", "!q", "b"), {}, "(!b U !q)"),
        (("U", "!p", "!q"), {}, "(q U !p)"),
        (("U", "!!p", "!!q"), {}, "(!q U p)"),
        (("F", "w"), {"w": "!w"}, "F(w)"),              # (!w -> F(w)) = F(w)
        (("F", "w"), {"w": "!!w"}, "true"),             # (w -> F(w)) = true
        (("U", "a", "b"), {"a": "!a"}, "(!b U a)"),
        (("U", "a", "!a"), {"a": "c"}, "(c -> a)"),
        (("U", "a", "b"), {"a": "!c"}, "(!c -> (!b U a))"),
        (("G", "!!r"), {}, "G(r)"),
    ]
    for key, conds, text in cases:
        assert clause_specification(key, conds).readable() == text, (key, conds)


def test_the_texts_of_the_issue():
    spec = Specification(globals=["!r"], eventuals=["!q"],
                         orders=[("!q", "q"), ("p", "!p"), ("a", "!p")])
    assert spec.to_ltl() == "G(!r) & F(!q) & (!q U !q) & (!!p U a) & (!!p U p)"  # recorded
    assert spec.readable() == "G(!r) & F(!q) & !q & (p U a) & p"
    assert unicode_ltl(spec) == "□(¬r) ∧ ◇(¬q) ∧ ¬q ∧ (p U a) ∧ p"
    assert spec.readable(vacuous=[("U", "p", "!p")]) == \
        "G(!r) & F(!q) & !q & (p U a)  [untested: p]"


def test_a_column_named_with_a_bang_that_is_no_negation_stays_an_atom():
    spec = Specification(globals=["!x"], orders=[("a", "!x")])
    for negations in ({}, False, {"!y": "y"}):
        text = spec.readable(negations=negations)
        assert text == 'G("!x") & (!"!x" U a)'
        # read back as the atom "!x": the same truth as the specification's on its columns
        formula = parse_ltl(text)
        assert formula.atoms == {"!x", "a"}
        names = ["!x", "a", "x"]
        for steps in itertools.product(itertools.product([0, 1], repeat=3), repeat=3):
            trace = np.array(steps)
            assert formula.satisfied_by(trace, names) == spec.satisfied_by(trace, names)
    assert unicode_ltl(spec, negations=False) == '□("!x") ∧ (¬"!x" U a)'
    assert spec.to_ltl() == "G(!x) & (!!x U a)"  # the recorded form does not change
    # the default reads the name as the augmenter's negation
    assert spec.readable() == "G(!x) & (x U a)"


def test_a_mapping_names_negations_of_any_prefix():
    import pandas as pd

    from bsi_sklearn.data.preprocessing import NegationAugmenter

    aug = NegationAugmenter(prefix="not_").fit([pd.DataFrame({"a": [1, 0], "b": [0, 1]})])
    assert aug.negations_ == {"not_a": "a", "not_b": "b"}
    spec = Specification(globals=["not_a"], orders=[("b", "not_a"), ("not_b", "b")])
    assert spec.readable(negations=aug.negations_) == "G(!a) & (a U b) & !b"
    assert spec.readable() == "G(not_a) & (!not_a U b) & (!b U not_b)"
    unnamed = NegationAugmenter(propositions=[1]).fit(np.zeros((2, 3, 2)))
    assert unnamed.negations_ == {2: 1}
    assert Specification(orders=[(0, 2)]).readable(negations=unnamed.negations_) == "(1 U 0)"


@pytest.mark.parametrize("bad", [["!p"], "!p", 3])
def test_negations_must_be_none_false_or_a_mapping(bad):
    with pytest.raises(ValueError, match="readable: negations must be None"):
        Specification(globals=["p"]).readable(negations=bad)


def test_negations_that_negate_themselves_are_refused():
    with pytest.raises(ValueError, match="is not another column"):
        Specification(globals=["p"]).readable(negations={"p": "p"})
    with pytest.raises(ValueError, match="negates itself"):
        Specification(globals=["p"]).readable(negations={"p": "q", "q": "p"})


# --------------------------------------------------------------------- the export (flloat)
@pytest.mark.parametrize("key, conds", KEYS[::3], ids=lambda v: repr(v))
def test_the_ltlf_export_is_over_the_atoms_and_means_the_clause(key, conds):
    pytest.importorskip("flloat")
    from flloat.parser.ltlf import LTLfParser

    spec = clause_specification(key, conds)
    text = spec.to_ltlf(dialect="ltlf2dfa")
    assert "!!" not in text and "!(!" not in text
    assert spec.to_ltlf(dialect="spot") == text  # p and q are plain atoms for Spot too
    formula = LTLfParser()(text)
    assert formula.find_labels() <= set(BASE)
    short = [i for i, tr in enumerate(TRACES) if len(tr) <= 3]
    got = [formula.truth([dict(zip(BASE, map(bool, s))) for s in TRACES[i]], 0) for i in short]
    np.testing.assert_array_equal(got, _project_truth(key, conds)[short], err_msg=text)
