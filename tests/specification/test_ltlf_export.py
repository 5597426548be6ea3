"""``to_ltlf`` round-trips through the real parsers (issue 21): Spot's scanner rules and flloat.

Spot cannot be installed from the package registries here, so its test runs only where the
``spot`` Python module is present; the atom rules of its scanner (``spot/parsetl/scantl.ll``)
are mirrored below as an oracle and checked on every name hypothesis draws.
"""

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bsi_sklearn import Specification
from bsi_sklearn.specification.ltlf_export import spot_atom, to_ltlf

flloat = pytest.importorskip("flloat")

# --------------------------------------------------------------------- Spot's scanner, mirrored
# Flex rules of scantl.ll in order (longest match wins, the earlier rule on a tie); only those
# that can match at the start of an atom's text.
_SPOT_RULES = [
    ("const", r"1|[tT][rR][uU][eE]"),
    ("const", r"0|[fF][aA][lL][sS][eE]"),
    ("op", r"!|~"),
    ("op", r"first_match"),
    ("op", r"\|\||\||\+|\\/"),
    ("op", r"&&|/\\"),
    ("op", r"&"),
    ("op", r"\^|xor"),
    ("op", r"->|=>|-->"),
    ("op", r"<->|<=>|<-->"),
    ("op", r"[XFG][ \t\n\r]*\[\]?"),
    ("op", r"F|<>|G|\[\]|U|R|V|X|\(\)|W|M"),
    ("op", r"=0|=1"),
    ("atom", r"[a-zA-EH-WYZ_.][a-zA-Z0-9_.]*|[FGX][0-9][a-zA-Z0-9_.]*"),
]


def spot_scan_atom(text):
    """The name of the one atomic proposition Spot reads in ``text``, or None."""
    if text.startswith('"'):
        out, k = [], 1
        while k < len(text):
            c = text[k]
            if c == "\\" and k + 1 < len(text):
                out.append(text[k + 1])
                k += 2
            elif c == '"':
                return "".join(out) if k == len(text) - 1 else None
            else:
                out.append(c)
                k += 1
        return None
    best, kind = 0, None
    for name, pattern in _SPOT_RULES:
        m = re.match(pattern, text)
        if m and len(m.group()) > best:
            best, kind = len(m.group()), name
    return text if kind == "atom" and best == len(text) else None


NAMES = st.text(alphabet=st.sampled_from(list("FGXURVWMtruefalsxo_.aZ09 -\\\"'")),
                min_size=1, max_size=8)


@settings(max_examples=400, deadline=None)
@given(name=NAMES)
def test_spot_reads_every_written_atom_back(name):
    assert spot_scan_atom(spot_atom(name)) == name


@pytest.mark.parametrize("name", ["GPS_ok", "Fuel", "Xpos", "True", "TRUE", "false", "V", "R",
                                  "U", "W", "M", "xor", "first_match", "a\\b", 'say "hi"', "0",
                                  "Threat-1", "1x"])
def test_names_spot_would_misread_are_quoted(name):
    text = to_ltlf(Specification(globals=[name]), dialect="spot")
    assert text.startswith('G("') and spot_scan_atom(text[2:-1]) == name
    assert spot_scan_atom(name) != name  # unquoted, Spot reads something else


@pytest.mark.parametrize("name", ["safe", "a_ok", "Hx", "p0", "trueish", "Vx", "Up"])
def test_plain_names_stay_plain(name):
    assert to_ltlf(Specification(globals=[name]), dialect="spot") == f"G({name})"


def test_real_spot_parses_the_text():
    spot = pytest.importorskip("spot")
    if not hasattr(spot, "formula"):
        pytest.skip("the spot module here is not Spot's Python binding")
    names = ["GPS_ok", "Fuel", "True", "V", "a\\b", 'say "hi"', "safe", 0]
    spec = Specification(globals=names[:4], eventuals=names[4:7], orders=[("safe", 0)])
    f = spot.formula(to_ltlf(spec, dialect="spot"))
    assert {str(ap.ap_name()) for ap in f.ap()} == {str(n) for n in names}


# --------------------------------------------------------------------- flloat / LTLf2DFA
def _flloat_atoms(text):
    from flloat.parser.ltlf import LTLfParser

    return LTLfParser()(text).find_labels()


@pytest.mark.parametrize("name, word", [("lastly", "last"), ("true_x", "true"),
                                        ("ending", "end"), ("falsey", "false"),
                                        ("end", "end")])
def test_names_flloat_cannot_parse_are_refused(name, word):
    spec = Specification(globals=[name])
    with pytest.raises(ValueError, match=rf"proposition '{name}' is not an LTLf2DFA / flloat "
                                         rf"atom: the parser reads the keyword '{word}'"):
        to_ltlf(spec, dialect="ltlf2dfa")
    renamed = to_ltlf(spec, dialect="ltlf2dfa", atoms={name: "q"})
    assert renamed == "G(q)" and _flloat_atoms(renamed) == {"q"}


def test_readme_quick_start_integer_propositions():
    spec = Specification(globals=[0], eventuals=[1, 2], orders=[(1, 2)])
    text = spec.to_ltlf(dialect="ltlf2dfa")
    assert text == "G(p0) & F(p1) & F(p2) & (!(p2) U (p1))"
    assert _flloat_atoms(text) == {"p0", "p1", "p2"}


def test_atoms_are_checked_and_distinct():
    spec = Specification(globals=["a", "b"])
    with pytest.raises(ValueError, match=r"atoms\['a'\] = 'Last' is not an LTLf2DFA"):
        to_ltlf(spec, dialect="ltlf2dfa", atoms={"a": "Last"})
    with pytest.raises(ValueError, match="propositions 'a' and 'b' are both written 'b'"):
        to_ltlf(spec, dialect="ltlf2dfa", atoms={"a": "b"})
    with pytest.raises(ValueError, match="propositions 0 and 'p0' are both written 'p0'"):
        to_ltlf(Specification(globals=[0, "p0"]), dialect="ltlf2dfa")
    with pytest.raises(ValueError, match="atoms must be a mapping"):
        to_ltlf(spec, atoms=["x"])
    assert to_ltlf(spec, atoms={"a": "G1"}) == 'G("G1") & G(b)'


LTLF_NAMES = st.text(alphabet=st.sampled_from(list("truefalsndxyz_09TE")), min_size=1,
                     max_size=7)


@settings(max_examples=60, deadline=None)
@given(names=st.lists(LTLF_NAMES, min_size=3, max_size=3, unique=True),
       trace=st.lists(st.lists(st.booleans(), min_size=3, max_size=3), min_size=1, max_size=4))
def test_flloat_reads_the_same_formula_or_the_name_is_refused(names, trace):
    a, b, c = names
    spec = Specification(globals=[a], eventuals=[b], orders=[(b, c)])
    try:
        text = to_ltlf(spec, dialect="ltlf2dfa")
    except ValueError as exc:
        assert "is not an LTLf2DFA / flloat atom" in str(exc)
        return
    from flloat.parser.ltlf import LTLfParser

    formula = LTLfParser()(text)
    assert formula.find_labels() == set(names)
    word = [dict(zip(names, step)) for step in trace]
    assert formula.truth(word, 0) is spec.satisfied_by(np.array(trace), feature_names=names)


# --------------------------------------------------------------------- negated columns
def test_a_negated_column_is_exported_as_the_negation_of_its_atom():
    spec = Specification(globals=["!r"], eventuals=["!q"], orders=[("a", "!p"), ("!q", "b")],
                         conditions={"a": "!c"})
    text = "G(!r) & F(!q) & (!(b) U (!q)) & (!c -> ((p) U (a)))"
    assert to_ltlf(spec, dialect="ltlf2dfa") == to_ltlf(spec, dialect="spot") == text
    assert _flloat_atoms(text) == {"a", "b", "c", "p", "q", "r"}
    # Spot reads every atom of the text plain: no quoted "!q" is left
    assert spot_scan_atom("r") == "r" and '"' not in text
    # before: Spot got atoms named "!q", LTLf2DFA refused them; negations=False keeps that
    assert to_ltlf(Specification(globals=["!q"]), negations=False) == 'G("!q")'
    with pytest.raises(ValueError, match="proposition '!q' is not an LTLf2DFA"):
        to_ltlf(Specification(globals=["!q"]), dialect="ltlf2dfa", negations=False)


def test_the_negation_of_a_spot_name_is_quoted_and_atoms_given_win():
    spec = Specification(globals=["!Fuel"], orders=[("a", "!GPS")])
    assert to_ltlf(spec) == 'G(!"Fuel") & (("GPS") U (a))'
    # an identifier given in atoms is that atom, not a negation
    assert to_ltlf(spec, atoms={"!Fuel": "nofuel"}) == 'G(nofuel) & (("GPS") U (a))'
    # a mapping names the negations of any prefix, and only those
    other = Specification(globals=["not_r", "!x"])
    assert to_ltlf(other, negations={"not_r": "r"}) == 'G("!x") & G(!r)'


@settings(max_examples=40, deadline=None)
@given(trace=st.lists(st.lists(st.booleans(), min_size=3, max_size=3), min_size=1, max_size=5))
def test_flloat_reads_the_negations_as_the_augmented_columns_mean(trace):
    from flloat.parser.ltlf import LTLfParser

    from bsi_sklearn.data.preprocessing import add_negations

    names = ["a", "b", "c"]
    spec = Specification(globals=["!c"], eventuals=["a"],
                         orders=[("a", "!b"), ("!a", "b"), ("b", "!b")], conditions={"a": "!b"})
    formula = LTLfParser()(to_ltlf(spec, dialect="ltlf2dfa"))
    word = [dict(zip(names, step)) for step in trace]
    augmented = add_negations(np.array([trace]))[0]  # columns a, b, c, !a, !b, !c
    assert formula.truth(word, 0) is spec.satisfied_by(
        augmented, feature_names=names + ["!a", "!b", "!c"])
