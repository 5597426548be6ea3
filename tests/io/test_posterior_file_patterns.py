"""The posterior file, version 2: pattern candidates in the roles, clauses in the entries."""

import json
from pathlib import Path

import numpy as np
import pytest

from bsi_sklearn.data.roles import Roles
from bsi_sklearn.io.posterior_file import dump_posterior, parse_posterior
from bsi_sklearn.specification import Specification

NAMES = ["s", "a", "b", "c"]
PATTERNS = (("Response", (1, 2)), ("Choice", (3, 1)), ("G(x -> WX(!x))", (2,)))


def _roles(patterns=PATTERNS):
    return Roles(np.array([0]), np.array([1, 2]), np.array([-1, 3]), list(NAMES), patterns)


def _text(roles=None):
    roles = roles or _roles()
    specs = [Specification(globals=["s"], eventuals=["a"],
                           patterns=[("Response", ("a", "b")), ("Choice", ("c", "a"))]),
             Specification(orders=[("a", "b")], patterns=[("G(x -> WX(!x))", ["b"])]),
             Specification(eventuals=["b"], conditions={"b": "c"})]
    keys = [("G", "s"), ("P", "Response", ("a", "b")), ("P", "Choice", ("a", "c")),
            ("P", "G(x -> WX(!x))", ("b",)), ("F", "a"), ("F", "b"), ("U", "a", "b"),
            ("U", "b", "a")]
    return dump_posterior(roles, specs, [0.5, 0.3, 0.2], keys, np.linspace(0, 1, 8), 0.0)


def test_version_2_round_trips_the_patterns():
    text = _text()
    doc = json.loads(text)
    assert doc["version"] == 2
    assert doc["roles"]["patterns"] == [["Response", ["a", "b"]], ["Choice", ["c", "a"]],
                                        ["G(x -> WX(!x))", ["b"]]]
    assert doc["specifications"][0]["patterns"] == [["Choice", ["a", "c"]],
                                                    ["Response", ["a", "b"]]]
    assert doc["specifications"][0]["ltl"] == "G(s) & F(a) & Choice(a, c) & Response(a, b)"
    back = parse_posterior(text)
    assert back.roles.patterns == PATTERNS
    # pattern k is global slot n_globals + k
    np.testing.assert_array_equal(back.tau_masks, [[1, 1, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]])
    assert back.marginal_keys[1:4] == [("P", "Response", ("a", "b")), ("P", "Choice", ("a", "c")),
                                       ("P", "G(x -> WX(!x))", ("b",))]
    assert dump_posterior(back.roles, *_specs_of(back), back.probabilities, back.marginal_keys,
                          back.marginals, 0.0) == text


def _specs_of(doc):
    r = doc.roles
    g, s, p = r.global_names(), r.subtask_names(), r.pattern_keys()
    out = []
    for h in range(len(doc.probabilities)):
        tau = doc.tau_masks[h]
        orders = [(s[a], s[b]) for b, a in enumerate(doc.structures[h]) if a >= 0]
        out.append(Specification([g[j] for j in np.flatnonzero(tau[:len(g)])],
                                 [s[w] for w in np.flatnonzero(doc.w1_masks[h])], orders,
                                 r.condition_names(),
                                 patterns=[p[k] for k in np.flatnonzero(tau[len(g):])]))
    return (out,)


def test_without_patterns_the_file_is_version_1_and_still_reads():
    roles = _roles(())
    specs = [Specification(globals=["s"], eventuals=["a"])]
    text = dump_posterior(roles, specs, [1.0], [("G", "s"), ("F", "a")], [1.0, 1.0], 0.0)
    doc = json.loads(text)
    assert doc["version"] == 1 and "patterns" not in doc["roles"]
    assert "patterns" not in doc["specifications"][0]
    back = parse_posterior(text)
    assert back.roles.patterns == () and back.tau_masks.shape == (1, 1)
    with pytest.raises(ValueError, match="the roles list no pattern candidate"):
        dump_posterior(roles, [Specification(patterns=[("Existence", ["a"])])], [1.0], [], [],
                       0.0)


def _edited(edit):
    doc = json.loads(_text())
    edit(doc)
    return json.dumps(doc)


@pytest.mark.parametrize("edit, message", [
    (lambda d: d["roles"]["patterns"].append(["Respons", ["a", "b"]]),
     r"roles.patterns\[3\]: unknown template 'Respons'"),
    (lambda d: d["roles"]["patterns"].append(["Response", ["a"]]),
     r"roles.patterns\[3\]: pattern 'Response' has 2 slots"),
    (lambda d: d["roles"]["patterns"].append(["Response", ["a", "zz"]]),
     r"roles.patterns\[3\]\[1\]\[1\]: 'zz' is not one of the names"),
    (lambda d: d["roles"]["patterns"].append(["Response", ["a", "b"]]),
     r"roles.patterns\[3\]: listed twice"),
    (lambda d: d["specifications"][1]["patterns"].append(["Response", ["b", "a"]]),
     r"specifications\[1\].patterns\[1\]: Response\['b', 'a'\] is not one of the pattern "
     "candidates"),
    (lambda d: d["specifications"][1]["patterns"].pop(),
     r"specifications\[1\].ltl: .* is not the formula of the entry's clauses"),
    (lambda d: d["specifications"][2].pop("patterns"),
     r"specifications\[2\]: missing field 'patterns'"),
    (lambda d: d.update(version=1), r"roles: unknown field 'patterns'"),
    (lambda d: d["clause_marginals"][1][0].__setitem__(1, "Nope"),
     r"clause_marginals\[1\]\[0\]: unknown template 'Nope'"),
])
def test_bad_version_2_files_name_the_field(edit, message):
    with pytest.raises(ValueError, match=message):
        parse_posterior(_edited(edit))


def test_version_2_files_follow_the_published_schema():
    jsonschema = pytest.importorskip("jsonschema")
    root = Path(__file__).resolve().parents[2]
    schema = json.loads((root / "docs" / "posterior-schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    jsonschema.validate(json.loads(_text()), schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(json.loads(_edited(lambda d: d["roles"].pop("patterns"))), schema)
