"""Which pattern clauses a fit considers, and how probable each is a priori (DESIGN §12).

The templates a user asks for (``BSIClassifier(templates=[...])``) are instantiated over the
propositions that hold at some step of some training demonstration (a slot filled by a
proposition that never holds says nothing the data can test), and an instance that every
training demonstration satisfies is set apart: it is vacuous, and under the complexity-based
likelihood it would be rewarded for its size alone. What is left are the pattern candidates,
global slots after the ``G`` candidates (:class:`bsi_sklearn.data.roles.Roles`), each an
independent inclusion with its template family's probability.
"""

import math
from numbers import Real

import numpy as np

from bsi_sklearn.model.patterns import get_template, instantiate, pattern_truth
from bsi_sklearn.specification.templates import TEMPLATE_SETS

__all__ = ["FAMILY_P", "MAX_PATTERN_CANDIDATES", "check_templates", "check_p_patterns",
           "pattern_probabilities", "pattern_candidates"]

#: Default inclusion probability of a pattern clause, by template family: the simpler
#: families (one proposition) more likely than the relations, the relations than the
#: orderings, scopes and negations. A prior, not a tuned value; a user sets ``p_patterns``.
FAMILY_P = {"existence": 0.2, "absence": 0.2, "choice": 0.1, "relation": 0.1,
            "ordering": 0.05, "negation": 0.05, "scoped": 0.05, "user": 0.1}

#: Most pattern candidates a fit takes: each is one more coordinate of every sweep and one
#: more clause column of the truth (DESIGN §5); past it the fit stops and says what to do.
MAX_PATTERN_CANDIDATES = 5000


def check_templates(templates):
    """The templates of ``templates``, each checked; a tuple of names.

    ``"paper"``: none; a name of :data:`~bsi_sklearn.specification.templates.TEMPLATE_SETS`:
    its templates.

    Raises
    ------
    ValueError
        For anything but ``"paper"``, a set's name or a non-empty list of distinct template
        names or LTLf
        formulas with placeholders (:func:`~bsi_sklearn.model.patterns.get_template` says
        what is wrong with one).

    Examples
    --------
    >>> check_templates(["Response", "G(x -> F(y))"])
    ('Response', 'G(x -> F(y))')
    >>> check_templates("paper")
    ()
    >>> check_templates("unary")
    ('Existence', 'Absence', 'AtMostOnce', 'Init', 'Universality')
    """
    if isinstance(templates, str):
        if templates == "paper":
            return ()
        if templates in TEMPLATE_SETS:
            return TEMPLATE_SETS[templates]
        sets = ", ".join(map(repr, TEMPLATE_SETS))
        raise ValueError(f"templates must be 'paper', a set's name ({sets}) or a list of "
                         f"template names or LTLf formulas, got the string {templates!r} (a "
                         f"list of one template is [{templates!r}])")
    try:
        items = list(templates)
    except TypeError:
        raise ValueError(f"templates must be 'paper' or a list of template names or LTLf "
                         f"formulas, got {templates!r}") from None
    if not items:
        raise ValueError("templates is an empty list; use templates='paper' for the paper's "
                         "template alone")
    names = []
    for item in items:
        try:
            name = get_template(item).name
        except (TypeError, ValueError) as err:
            raise ValueError(f"templates: {err}") from None
        if name in names:
            raise ValueError(f"templates: {name!r} is listed more than once")
        names.append(name)
    return tuple(names)


def pattern_probabilities(names, p_patterns):
    """Inclusion probability of each template of ``names`` under ``p_patterns``.

    ``p_patterns`` is ``None`` (:data:`FAMILY_P`), a probability for every template, or a
    mapping from template family (``"relation"``) or template name (``"Response"``) to a
    probability, the name taking precedence; families and names it does not give keep
    :data:`FAMILY_P`.

    Examples
    --------
    >>> pattern_probabilities(("Response", "Absence"), {"Response": 0.3})
    {'Response': 0.3, 'Absence': 0.2}
    """
    out = {}
    for name in names:
        family = get_template(name).family
        if p_patterns is None:
            p = FAMILY_P[family]
        elif isinstance(p_patterns, Real) and not isinstance(p_patterns, bool):
            p = float(p_patterns)
        else:
            p = p_patterns.get(name, p_patterns.get(family, FAMILY_P[family]))
        if isinstance(p, bool) or not isinstance(p, Real) or not 0.0 < float(p) < 1.0:
            raise ValueError(f"p_patterns: the inclusion probability of {name!r} (family "
                             f"{family!r}) must be a number in (0, 1), got {p!r}")
        out[name] = float(p)
    return out


def check_p_patterns(p_patterns):
    """Whether ``p_patterns`` has a valid form (the values are checked at fit)."""
    if p_patterns is None:
        return True
    if isinstance(p_patterns, Real) and not isinstance(p_patterns, bool):
        return 0.0 < float(p_patterns) < 1.0
    if hasattr(p_patterns, "items"):
        return all(isinstance(k, str) for k in p_patterns)
    return False


def _n_instances(name, n_props):
    # How many tuples instantiate(name, ...) lists over n_props propositions.
    t = get_template(name)
    return (math.comb if t.symmetric else math.perm)(n_props, len(t.slots))


def pattern_candidates(traces, names, max_candidates=MAX_PATTERN_CANDIDATES):
    """The pattern candidates of a fit: ``(template name, columns)`` of each kept instance.

    Parameters
    ----------
    traces : Traces
        The training demonstrations.
    names : tuple of str
        Template names (:func:`check_templates`).
    max_candidates : int
        Most instances instantiated; more is a ``ValueError`` naming the count.

    Returns
    -------
    candidates : tuple of (str, tuple of int)
        In the order of ``names``, then of :func:`~bsi_sklearn.model.patterns.instantiate`
        over the propositions that hold somewhere; the instances every demonstration
        satisfies left out.
    truth : ndarray of shape (n_demos, len(candidates)), uint8
        Their truth on the demonstrations, computed here to find the vacuous ones: the
        clause truth of the fit takes it (:func:`bsi_sklearn.model.clauses.clause_truth`'s
        ``pattern_block``) rather than computing it again.
    n_vacuous : int
        How many instances were set apart as vacuous.
    """
    data = np.ascontiguousarray(traces.data, dtype=np.uint8)
    held = np.flatnonzero(data.any(axis=0)).tolist()
    # Counted before any is listed: a three-slot template over 200 propositions is 7.9e6.
    count = sum(_n_instances(name, len(held)) for name in names)
    if count > max_candidates:
        raise ValueError(
            f"templates {list(names)} over the {len(held)} propositions that hold somewhere "
            f"make {count:,} pattern candidates, more than {max_candidates:,}: each is a "
            "coordinate of the sampler and a column of the clause truth. Ask for fewer "
            "templates, or select the propositions first (for example a ColumnTransformer "
            "or fewer activities)")
    out, blocks, n_vacuous = [], [np.zeros((len(traces.offsets) - 1, 0), np.uint8)], 0
    for name in names:
        cols = np.array(instantiate(name, held), dtype=np.int64)
        if not len(cols):
            continue
        truth = pattern_truth(name, data, traces.offsets, cols)
        keep = ~truth.all(axis=0)
        n_vacuous += int((~keep).sum())
        out.extend((name, tuple(int(c) for c in row)) for row in cols[keep])
        blocks.append(truth[:, keep])
    return tuple(out), np.concatenate(blocks, axis=1), n_vacuous
