"""The report's wording of pattern clauses: the template's own sentence, its Declare name."""

import numpy as np
import pytest

from bsi_sklearn.report.wording import (
    clause_sentence,
    describe_specification,
    event_log_sentence,
    ordered_clauses,
    unicode_ltl,
    violated_clauses,
)
from bsi_sklearn.specification import Specification

SPEC = Specification(globals=["safe"], patterns=[("Response", ("order", "pay")),
                                                 ("G(x -> WX(!x))", ["pay"])])


def test_pattern_clauses_are_said_by_their_template_sentence():
    assert ordered_clauses(SPEC) == [("G", "safe"), ("P", "Response", ("order", "pay")),
                                     ("P", "G(x -> WX(!x))", ("pay",))]
    assert describe_specification(SPEC) == [
        "Always, safe holds.",
        "Response(order, pay): every order is eventually followed by pay.",
        "G(pay -> WX(!pay)) holds."]
    key = ("P", "Response", ("order", "pay"))
    assert event_log_sentence(key) == clause_sentence(key)
    assert unicode_ltl(SPEC) == "□(safe) ∧ Response(order, pay) ∧ {G(x -> WX(!x))}(pay)"
    assert unicode_ltl(SPEC, vacuous=[key]).endswith("[untested: Response(order, pay)]")


def test_violated_clauses_name_the_pattern_clause():
    trace = np.array([[1, 1, 0], [1, 0, 1], [1, 0, 1]])  # safe, order, pay
    assert violated_clauses(SPEC, trace, ["safe", "order", "pay"]) == [
        ("P", "G(x -> WX(!x))", ("pay",))]


def test_a_bad_pattern_key_is_named():
    with pytest.raises(ValueError, match=r"\('P', template, propositions\)"):
        clause_sentence(("P", "Response", "ab"))
