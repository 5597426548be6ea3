"""Metrics comparing inferred specifications (or posteriors) with a ground truth."""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from bsi_sklearn.specification import Specification

__all__ = [
    "OrderClassification",
    "OrderCounts",
    "jaccard_similarity",
    "expected_similarity",
    "best_similarity",
    "classify_orders",
    "expected_order_counts",
]


class OrderClassification(NamedTuple):
    """The orders of an inferred specification, split against a ground truth.

    Attributes
    ----------
    correct : frozenset of (a, b)
        Orders that the ground truth also contains.
    incorrect : frozenset of (a, b)
        Orders ``(a, b)`` whose reverse ``(b, a)`` is a ground-truth order.
    extra : frozenset of (a, b)
        Every other order: it over-constrains the task without inducing wrong behaviour.
    """

    correct: frozenset
    incorrect: frozenset
    extra: frozenset

    @property
    def counts(self):
        """The three set sizes as an :class:`OrderCounts`."""
        return OrderCounts(len(self.correct), len(self.incorrect), len(self.extra))


class OrderCounts(NamedTuple):
    """Numbers (or posterior expectations) of correct, incorrect and extra orders."""

    correct: float
    incorrect: float
    extra: float


def _check_spec(spec, name):
    if not isinstance(spec, Specification):
        raise ValueError(f"{name} must be a Specification, got {type(spec).__name__}")
    return spec


def jaccard_similarity(spec, truth):
    """Jaccard index between the clause sets of two specifications (paper eq. 13).

    ``L = |C(spec) & C(truth)| / |C(spec) | C(truth)|`` where ``C`` is
    :meth:`Specification.clauses` (globals, eventuals and the transitively closed orders).
    Two empty specifications are identical: their similarity is 1.

    Parameters
    ----------
    spec : Specification
        The candidate (inferred) specification.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    similarity : float
        In ``[0, 1]``; 1 exactly when both specifications have the same clauses.

    See Also
    --------
    expected_similarity : the same index averaged over a posterior.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(globals=["t"], eventuals=["a", "b"], orders=[("a", "b")])
    >>> spec = Specification(globals=["t"], eventuals=["a"])
    >>> jaccard_similarity(spec, truth)
    0.5
    """
    a = _check_spec(spec, "spec").clauses()
    b = _check_spec(truth, "truth").clauses()
    union = len(a | b)
    if union == 0:
        return 1.0
    return len(a & b) / union


def _as_distribution(posterior):
    """Return ``(specifications, probabilities)`` sorted by descending probability.

    Accepts an object with ``specifications`` and ``probabilities`` attributes (a
    ``Posterior``), a mapping ``Specification -> probability`` or a sequence of
    ``(Specification, probability)`` pairs. Probabilities are normalised to sum to 1.
    """
    if hasattr(posterior, "specifications") and hasattr(posterior, "probabilities"):
        specs = list(posterior.specifications)
        probs = posterior.probabilities
    elif isinstance(posterior, Specification):
        specs, probs = [posterior], [1.0]
    else:
        if isinstance(posterior, Mapping):
            pairs = list(posterior.items())
        else:
            try:
                pairs = list(posterior)
            except TypeError:
                raise ValueError(
                    "posterior must be a Posterior, a mapping Specification -> probability or "
                    f"a sequence of (Specification, probability) pairs, got "
                    f"{type(posterior).__name__}"
                ) from None
        specs, probs = [], []
        for i, pair in enumerate(pairs):
            try:
                s, p = pair
            except (TypeError, ValueError):
                raise ValueError(
                    f"posterior entry {i} is not a (Specification, probability) pair"
                ) from None
            specs.append(s)
            probs.append(p)
    try:
        probs = np.asarray(probs, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError("posterior probabilities must be numbers") from None
    if probs.ndim != 1 or len(probs) != len(specs):
        raise ValueError(
            f"posterior has {len(specs)} specifications but probabilities of shape "
            f"{probs.shape}"
        )
    if len(specs) == 0:
        raise ValueError("posterior is empty: it holds no specification")
    for i, s in enumerate(specs):
        if not isinstance(s, Specification):
            raise ValueError(
                f"posterior entry {i} is not a Specification (got {type(s).__name__})"
            )
    if not np.all(np.isfinite(probs)) or np.any(probs < 0):
        raise ValueError("posterior probabilities must be finite and non-negative")
    total = probs.sum()
    if total <= 0:
        raise ValueError("posterior probabilities sum to zero")
    order = np.argsort(-probs, kind="stable")
    return [specs[i] for i in order], probs[order] / total


def expected_similarity(posterior, truth):
    """Posterior expectation of the Jaccard similarity to the ground truth.

    ``E[L] = sum_phi P(phi | D) L(phi)``, the paper's measure of how far the inferred
    distribution lies from the ground truth.

    Parameters
    ----------
    posterior : Posterior, mapping or sequence of (Specification, float)
        Anything with ``specifications`` and ``probabilities`` attributes, a mapping
        ``Specification -> probability``, or ``(Specification, probability)`` pairs.
        Probabilities are normalised to sum to 1.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    similarity : float

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(eventuals=["a", "b"])
    >>> posterior = [(truth, 0.75), (Specification(eventuals=["a"]), 0.25)]
    >>> expected_similarity(posterior, truth)
    0.875
    """
    specs, probs = _as_distribution(posterior)
    _check_spec(truth, "truth")
    sims = np.array([jaccard_similarity(s, truth) for s in specs])
    return float(np.dot(probs, sims))


def best_similarity(posterior, truth, k=5):
    """Highest Jaccard similarity among the ``k`` most probable specifications.

    Parameters
    ----------
    posterior : Posterior, mapping or sequence of (Specification, float)
        See :func:`expected_similarity`.
    truth : Specification
        The ground-truth specification.
    k : int, default=5
        How many of the most probable specifications to consider (the paper uses 5); ties
        in probability keep the posterior's own order.

    Returns
    -------
    similarity : float
        1.0 exactly when the ground truth is among the top ``k``.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(eventuals=["a", "b"])
    >>> posterior = [(Specification(eventuals=["a"]), 0.6), (truth, 0.4)]
    >>> best_similarity(posterior, truth, k=1), best_similarity(posterior, truth, k=2)
    (0.5, 1.0)
    """
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
        raise ValueError(f"k must be a positive integer, got {k!r}")
    specs, _ = _as_distribution(posterior)
    _check_spec(truth, "truth")
    return max(jaccard_similarity(s, truth) for s in specs[: int(k)])


def classify_orders(spec, truth):
    """Split the orders of ``spec`` into correct, incorrect and extra ones.

    An inferred order ``(a, b)`` (*a precedes b*) is *correct* if the ground truth contains
    it, *incorrect* if the ground truth contains its reverse ``(b, a)``, and *extra*
    otherwise. Both sets of orders are transitively closed, as :class:`Specification`
    stores them.

    Parameters
    ----------
    spec : Specification
        The inferred specification.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    classification : OrderClassification
        Named tuple of frozensets ``(correct, incorrect, extra)``; ``.counts`` gives their
        sizes.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(orders=[("a", "b"), ("b", "c")])
    >>> spec = Specification(orders=[("a", "b"), ("c", "a"), ("d", "a")])
    >>> result = classify_orders(spec, truth)
    >>> sorted(result.correct), sorted(result.incorrect), sorted(result.extra)
    ([('a', 'b')], [('c', 'a'), ('c', 'b')], [('d', 'a'), ('d', 'b')])
    >>> result.counts
    OrderCounts(correct=1, incorrect=2, extra=2)
    """
    inferred = _check_spec(spec, "spec").orders
    true = _check_spec(truth, "truth").orders
    correct = inferred & true
    incorrect = frozenset(p for p in inferred if (p[1], p[0]) in true)
    extra = inferred - correct - incorrect
    return OrderClassification(frozenset(correct), incorrect, frozenset(extra))


def expected_order_counts(posterior, truth):
    """Posterior expectation of the numbers of correct, incorrect and extra orders.

    Parameters
    ----------
    posterior : Posterior, mapping or sequence of (Specification, float)
        See :func:`expected_similarity`.
    truth : Specification
        The ground-truth specification.

    Returns
    -------
    counts : OrderCounts
        Named tuple of floats ``(correct, incorrect, extra)``.

    Examples
    --------
    >>> from bsi_sklearn.specification import Specification
    >>> truth = Specification(orders=[("a", "b")])
    >>> posterior = [(truth, 0.5), (Specification(orders=[("b", "a")]), 0.5)]
    >>> expected_order_counts(posterior, truth)
    OrderCounts(correct=0.5, incorrect=0.5, extra=0.0)
    """
    specs, probs = _as_distribution(posterior)
    _check_spec(truth, "truth")
    counts = np.array([classify_orders(s, truth).counts for s in specs], dtype=np.float64)
    total = probs @ counts
    return OrderCounts(float(total[0]), float(total[1]), float(total[2]))
