import pickle

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn import Specification
from bsi_sklearn.specification import transitive_closure


def test_canonical_equality_and_hash():
    a = Specification(globals=["s", "t"], eventuals=["x", "y"], orders=[("x", "y")])
    b = Specification(globals=("t", "s"), eventuals={"y", "x"}, orders={("x", "y")})
    assert a == b and hash(a) == hash(b)
    assert len({a, b}) == 1
    assert a != Specification(globals=["s"], eventuals=["x", "y"], orders=[("x", "y")])


def test_orders_are_transitively_closed_and_cycles_rejected():
    s = Specification(eventuals=["a"], orders=[("a", "b"), ("b", "c")])
    assert s.orders == {("a", "b"), ("b", "c"), ("a", "c")}
    assert s.n_conjuncts == 1 + 3
    with pytest.raises(ValueError, match="cycle"):
        Specification(orders=[("a", "b"), ("b", "a")])
    with pytest.raises(ValueError, match="itself"):
        transitive_closure([("a", "a")])
    with pytest.raises(ValueError, match="pair"):
        Specification(orders=["abc"])
    with pytest.raises(ValueError, match="globals"):
        Specification(globals="abc")


def test_clauses_and_ltl_strings():
    s = Specification(globals=["safe"], eventuals=["a", "b"], orders=[("a", "b")],
                      conditions={"a": "pa", "b": "pb", "zzz": "ignored"})
    assert s.clauses() == {("G", "safe"), ("F", "a"), ("F", "b"), ("U", "a", "b")}
    assert s.conditions == {"a": "pa", "b": "pb"}
    assert s.to_ltl() == "G(safe) & (pa -> F(a)) & (pb -> F(b)) & (pa -> (!b U a))"
    assert s.to_ltl(latex=True) == (
        r"\mathbf{G}(\mathit{safe}) \wedge (\mathit{pa} \rightarrow \mathbf{F}(\mathit{a})) "
        r"\wedge (\mathit{pb} \rightarrow \mathbf{F}(\mathit{b})) \wedge (\mathit{pa} "
        r"\rightarrow (\neg \mathit{b}\,\mathbf{U}\,\mathit{a}))"
    )
    assert Specification().to_ltl() == "true"
    assert str(s) == s.to_ltl()


def test_immutable_and_picklable():
    s = Specification(globals=[0], orders=[(1, 2)], conditions={1: 3})
    with pytest.raises(AttributeError):
        s.globals = frozenset()
    assert pickle.loads(pickle.dumps(s)) == s


def test_satisfied_by_semantics():
    names = ["safe", "a", "b", "pa"]
    spec = Specification(globals=["safe"], eventuals=["a"], orders=[("a", "b")],
                         conditions={"a": "pa"})
    ok = pd.DataFrame([[1, 0, 0, 1], [1, 1, 1, 1]], columns=names).astype(bool)
    assert spec.satisfied_by(ok)
    # b strictly before a violates the order
    bad = np.array([[1, 0, 1, 1], [1, 1, 0, 1]])
    assert not spec.satisfied_by(bad, feature_names=names)
    # condition false at t=0: eventual and order are vacuous; G still applies
    vac = np.array([[1, 0, 1, 0], [1, 0, 0, 1]])
    assert spec.satisfied_by(vac, feature_names=names)
    unsafe = np.array([[1, 1, 0, 1], [0, 1, 1, 1]])
    assert not spec.satisfied_by(unsafe, feature_names=names)
    with pytest.raises(ValueError, match="not a column"):
        Specification(globals=["nope"]).satisfied_by(ok)
    with pytest.raises(ValueError, match="0/1"):
        spec.satisfied_by(np.array([[2, 0, 0, 1]]), feature_names=names)
