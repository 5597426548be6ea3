"""Interpretability reports of a fitted classifier's MAP specification (Markdown and HTML)."""

from __future__ import annotations

import base64
import html
import numbers
import re
from collections.abc import Mapping
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd
from sklearn.metrics import confusion_matrix, f1_score
from sklearn.utils.validation import check_is_fitted

from bsi_sklearn import _report_figures as figures
from bsi_sklearn.specification import Specification
from bsi_sklearn.traces import check_consistent_traces, check_traces

__all__ = [
    "SpecificationReport",
    "clause_sentence",
    "clause_specification",
    "describe_specification",
    "explain",
    "ordered_clauses",
    "violated_clauses",
]

_KINDS = {"G": "global", "F": "eventual", "U": "order"}


# ---------------------------------------------------------------------------- clauses
def _sort_key(x):
    return (type(x).__name__, x)


def ordered_clauses(specification):
    """Clause keys of a specification in reading order: globals, eventuals, then orders.

    Keys are ``("G", p)``, ``("F", w)`` and ``("U", a, b)`` (*a precedes b*), as in
    :meth:`Specification.clauses`; within a kind they are sorted by identifier, the order
    of :meth:`Specification.clause_strings`.

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> ordered_clauses(Specification(globals=["safe"], eventuals=["b", "a"],
    ...                               orders=[("a", "b")]))
    [('G', 'safe'), ('F', 'a'), ('F', 'b'), ('U', 'a', 'b')]
    """
    spec = _check_spec(specification)
    return (
        [("G", p) for p in sorted(spec.globals, key=_sort_key)]
        + [("F", w) for w in sorted(spec.eventuals, key=_sort_key)]
        + [("U", a, b) for a, b in sorted(spec.orders,
                                          key=lambda o: (_sort_key(o[0]), _sort_key(o[1])))]
    )


def clause_specification(clause, conditions=None):
    """The one-clause :class:`Specification` of a clause key.

    Parameters
    ----------
    clause : tuple
        ``("G", p)``, ``("F", w)`` or ``("U", a, b)``.
    conditions : mapping, default=None
        Subtask -> condition proposition, as in :class:`Specification`.

    Returns
    -------
    Specification

    Examples
    --------
    >>> print(clause_specification(("U", "a", "b"), {"a": "a_ok"}).to_ltl())
    (a_ok -> (!b U a))
    """
    kind = _check_clause(clause)
    if kind == "G":
        return Specification(globals=[clause[1]])
    if kind == "F":
        return Specification(eventuals=[clause[1]], conditions=conditions)
    return Specification(orders=[(clause[1], clause[2])], conditions=conditions)


def _check_clause(clause):
    ok = isinstance(clause, tuple) and len(clause) >= 2 and clause[0] in _KINDS and (
        len(clause) == (3 if clause[0] == "U" else 2))
    if not ok:
        raise ValueError(
            f"clause {clause!r} is not a clause key ('G', p), ('F', w) or ('U', a, b)"
        )
    return clause[0]


def _check_descriptions(descriptions, names=None):
    if descriptions is None:
        return {}
    if not isinstance(descriptions, Mapping):
        raise ValueError(
            f"descriptions must be a mapping proposition -> phrase, got "
            f"{type(descriptions).__name__}"
        )
    for key, text in descriptions.items():
        if not isinstance(text, str) or not text.strip():
            raise ValueError(f"descriptions[{key!r}] must be a non-empty string, got {text!r}")
        if names is not None and key not in names:
            raise ValueError(
                f"descriptions: {key!r} is not a proposition of the classifier; known "
                f"propositions are {list(names)[:20]}{' ...' if len(names) > 20 else ''}"
            )
    return {k: " ".join(v.split()) for k, v in descriptions.items()}


def _phrase(ident, descriptions):
    return descriptions[ident] if ident in descriptions else f"{ident} holds"


def _capitalised(ident, descriptions):
    text = _phrase(ident, descriptions)
    if ident in descriptions and text[:1].islower():
        text = text[0].upper() + text[1:]
    return text


def clause_sentence(clause, conditions=None, descriptions=None):
    """One plain-English sentence for a clause.

    Every proposition is read through its phrase: ``descriptions[p]`` when given (a short
    statement in the present tense, e.g. ``"POI 3 is visited"``), else ``"p holds"``. With
    phrases ``P``, ``W``, ``A``, ``B`` and condition phrases ``C``:

    ==========================  =============================================
    clause                      sentence
    ==========================  =============================================
    ``G(p)``                    ``Always, P.``
    ``F(w)``                    ``Eventually, W.``
    ``pi_w -> F(w)``            ``If C, eventually W.``
    ``!b U a``                  ``A before B.`` (first letter capitalised)
    ``pi_a -> (!b U a)``        ``If C, A before B.``
    ==========================  =============================================

    "A before B" is the strong until of the template: A does happen, and B does not happen
    at an earlier step than A (both at the same step is fine). Conditions are read at the
    first step of a demonstration.

    Parameters
    ----------
    clause : tuple
        ``("G", p)``, ``("F", w)`` or ``("U", a, b)``.
    conditions : mapping, default=None
        Subtask -> condition proposition.
    descriptions : mapping, default=None
        Proposition -> short phrase.

    Returns
    -------
    str

    Examples
    --------
    >>> d = {"alive": "the strikers are alive", "omega_3": "POI 3 is visited",
    ...      "pi_3": "POI 3 is accessible", "omega_1": "POI 1 is visited",
    ...      "pi_1": "POI 1 is accessible"}
    >>> clause_sentence(("G", "alive"), descriptions=d)
    'Always, the strikers are alive.'
    >>> clause_sentence(("F", "omega_3"), {"omega_3": "pi_3"}, d)
    'If POI 3 is accessible, eventually POI 3 is visited.'
    >>> clause_sentence(("U", "omega_1", "omega_3"), descriptions=d)
    'POI 1 is visited before POI 3 is visited.'
    >>> clause_sentence(("F", "omega_2"))
    'Eventually, omega_2 holds.'
    """
    kind = _check_clause(clause)
    d = _check_descriptions(descriptions)
    cond = dict(conditions) if conditions is not None else {}
    if kind == "G":
        return f"Always, {_phrase(clause[1], d)}."
    if kind == "F":
        w = clause[1]
        if w in cond and cond[w] is not None:
            return f"If {_phrase(cond[w], d)}, eventually {_phrase(w, d)}."
        return f"Eventually, {_phrase(w, d)}."
    a, b = clause[1], clause[2]
    if a in cond and cond[a] is not None:
        return f"If {_phrase(cond[a], d)}, {_phrase(a, d)} before {_phrase(b, d)}."
    return f"{_capitalised(a, d)} before {_phrase(b, d)}."


def describe_specification(specification, descriptions=None):
    """One sentence per clause of a specification, in :func:`ordered_clauses` order.

    See :func:`clause_sentence` for the phrasing. The empty specification (``true``) has no
    clauses and gives an empty list.

    Examples
    --------
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(globals=["safe"], eventuals=["a"], orders=[("a", "b")])
    >>> for s in describe_specification(spec, {"safe": "the robot is safe"}):
    ...     print(s)
    Always, the robot is safe.
    Eventually, a holds.
    a holds before b holds.
    """
    spec = _check_spec(specification)
    return [clause_sentence(c, spec.conditions, descriptions) for c in ordered_clauses(spec)]


def violated_clauses(specification, trace, feature_names=None):
    """The clauses of a specification that a demonstration violates.

    Each clause is evaluated on its own, as the one-clause specification of
    :func:`clause_specification` (:meth:`Specification.satisfied_by` semantics). A clause whose
    condition is false at the first step is satisfied (vacuously).

    Parameters
    ----------
    specification : Specification
    trace : array-like of shape (T, n_props) or pandas.DataFrame
    feature_names : sequence, default=None
        Column names of ``trace``; taken from the DataFrame columns when omitted.

    Returns
    -------
    list of tuple
        Violated clause keys, in :func:`ordered_clauses` order.

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import Specification
    >>> spec = Specification(globals=["safe"], eventuals=["a", "b"], orders=[("a", "b")])
    >>> trace = np.array([[1, 0, 0], [0, 0, 1], [1, 1, 1]])  # b before a, unsafe once
    >>> violated_clauses(spec, trace, feature_names=["safe", "a", "b"])
    [('G', 'safe'), ('U', 'a', 'b')]
    """
    spec = _check_spec(specification)
    cond = spec.conditions
    return [c for c in ordered_clauses(spec)
            if not clause_specification(c, cond).satisfied_by(trace, feature_names)]


def _check_spec(spec):
    if not isinstance(spec, Specification):
        raise ValueError(f"specification must be a Specification, got {type(spec).__name__}")
    return spec


def _clause_condition(clause, conditions):
    if clause[0] == "G":
        return None
    return conditions.get(clause[1])


def _transitive_reduction(orders):
    orders = set(orders)
    succ = {}
    for a, b in orders:
        succ.setdefault(a, set()).add(b)
    return sorted(
        ((a, b) for a, b in orders
         if not any((c, b) in orders for c in succ.get(a, ()) if c != b)),
        key=lambda o: (_sort_key(o[0]), _sort_key(o[1])),
    )


# ---------------------------------------------------------------------------- document model
class _Code(NamedTuple):
    text: str


class _Doc:
    """A tiny document model rendered to Markdown and to HTML (one source, two outputs).

    Blocks: ``("h", level, text)``, ``("p", inline)``, ``("pre", text)``, ``("math", latex)``,
    ``("ul", [inline, ...])``, ``("table", header, rows)``, ``("figure", name, caption)``.
    Inline content is a str, a ``_Code`` or a list of both.
    """

    def __init__(self):
        self.blocks = []

    def add(self, *block):
        self.blocks.append(block)


_MD_SPECIAL = re.compile(r"([\\`*_\[\]<>|$#])")


def _md_text(text):
    return _MD_SPECIAL.sub(r"\\\1", str(text))


def _md_inline(inline):
    if isinstance(inline, _Code):
        text = inline.text.replace("\n", " ")
        fence = "``" if "`" in text else "`"
        pad = " " if fence == "``" else ""
        return f"{fence}{pad}{text}{pad}{fence}"
    if isinstance(inline, list):
        return "".join(_md_inline(x) for x in inline)
    return _md_text(inline).replace("\n", " ")


def _html_inline(inline):
    if isinstance(inline, _Code):
        return f"<code>{html.escape(inline.text)}</code>"
    if isinstance(inline, list):
        return "".join(_html_inline(x) for x in inline)
    return html.escape(str(inline))


def _render_markdown(doc, figure_files):
    out = []
    for block in doc.blocks:
        kind = block[0]
        if kind == "h":
            out.append(f"{'#' * block[1]} {_md_text(block[2])}")
        elif kind == "p":
            out.append(_md_inline(block[1]))
        elif kind == "pre":
            fence = "````" if "```" in block[1] else "```"
            out.append(f"{fence}text\n{block[1]}\n{fence}")
        elif kind == "math":
            out.append(f"$$\n{block[1]}\n$$")
        elif kind == "ul":
            out.append("\n".join(f"- {_md_inline(item)}" for item in block[1]))
        elif kind == "table":
            header, rows = block[1], block[2]
            lines = ["| " + " | ".join(_md_inline(h) for h in header) + " |",
                     "|" + "|".join("---" for _ in header) + "|"]
            lines += ["| " + " | ".join(_md_inline(c) for c in row) + " |" for row in rows]
            out.append("\n".join(lines))
        elif kind == "figure":
            name, caption = block[1], block[2]
            out.append(f"![{_md_text(caption)}]({figure_files[name]})\n\n*{_md_text(caption)}*")
    return "\n\n".join(out) + "\n"


_CSS = """
.bsi-report { font-family: -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif;
  max-width: 60em; line-height: 1.45; color: #1b1b1b; }
.bsi-report table { border-collapse: collapse; margin: 0.6em 0; }
.bsi-report th, .bsi-report td { border: 1px solid #ccc; padding: 0.25em 0.6em;
  text-align: left; vertical-align: top; }
.bsi-report th { background: #f0f3f7; }
.bsi-report pre { background: #f6f8fa; padding: 0.6em; overflow-x: auto;
  white-space: pre-wrap; }
.bsi-report code { font-family: Menlo, Consolas, monospace; font-size: 0.92em; }
.bsi-report figure { margin: 1em 0; }
.bsi-report img { max-width: 100%; }
.bsi-report figcaption { font-style: italic; color: #555; }
"""


def _render_html_body(doc, pngs):
    out = ['<div class="bsi-report">']
    for block in doc.blocks:
        kind = block[0]
        if kind == "h":
            out.append(f"<h{block[1]}>{html.escape(block[2])}</h{block[1]}>")
        elif kind == "p":
            out.append(f"<p>{_html_inline(block[1])}</p>")
        elif kind == "pre":
            out.append(f"<pre><code>{html.escape(block[1])}</code></pre>")
        elif kind == "math":
            out.append(f'<pre><code class="language-latex">{html.escape(block[1])}</code></pre>')
        elif kind == "ul":
            items = "".join(f"<li>{_html_inline(item)}</li>" for item in block[1])
            out.append(f"<ul>{items}</ul>")
        elif kind == "table":
            header, rows = block[1], block[2]
            head = "".join(f"<th>{_html_inline(h)}</th>" for h in header)
            body = "".join(
                "<tr>" + "".join(f"<td>{_html_inline(c)}</td>" for c in row) + "</tr>"
                for row in rows
            )
            out.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
        elif kind == "figure":
            name, caption = block[1], block[2]
            data = base64.b64encode(pngs[name]).decode("ascii")
            cap = html.escape(caption)
            out.append(f'<figure><img src="data:image/png;base64,{data}" alt="{cap}"/>'
                       f"<figcaption>{cap}</figcaption></figure>")
    out.append("</div>")
    return "\n".join(out)


# ---------------------------------------------------------------------------- report
class SpecificationReport:
    """What a fitted :class:`~bsi_sklearn.BSIClassifier` learned, ready to read and share.

    Built by :func:`explain`; render it with :meth:`to_markdown` (``report.md`` and PNG
    figures) or :meth:`to_html` (one self-contained file), or display it in a notebook.

    Attributes
    ----------
    title : str
    specification : Specification
        The MAP specification.
    ltl, ltl_latex : str
        The MAP specification as LTL text and as LaTeX.
    clauses : pandas.DataFrame
        One row per MAP clause (index: clause keys, reading order): ``kind`` (global,
        eventual, order), ``ltl``, ``latex``, ``sentence``, ``inclusion_probability``.
    descriptions : dict
        Proposition -> phrase used in the sentences.
    top : pandas.DataFrame
        The ``top_k`` most probable specifications, indexed by rank (from 1):
        ``probability``, ``ltl``, ``n_clauses`` and ``difference`` (the clauses added, ``+``,
        and removed, ``-``, relative to the MAP specification; empty for the MAP).
    map_probability, entropy : float
        Posterior probability of the MAP specification; entropy (nats) of the posterior.
    n_unique_specifications : int
    clause_marginals : pandas.Series
        Posterior inclusion probability of every candidate clause.
    order_edges : list of (a, b)
        Transitive reduction of the MAP orders (the arrows of the DAG figure).
    inference : dict
        How the posterior was obtained: ``method``, ``prior``, ``likelihood``,
        ``dropped_mass``, ``rhat`` (MCMC only).
    demo_names : list of str or None
        One name per demonstration (``None`` without ``X``).
    clause_states : pandas.DataFrame or None
        MAP clauses x demonstrations: 0 violated, 1 satisfied, 2 satisfied vacuously (the
        clause's condition is false).
    map_satisfied : ndarray of bool or None
        Whether each demonstration satisfies the MAP specification.
    proba : ndarray or None
        Posterior-vote probability that each demonstration is acceptable.
    predicted_acceptable : ndarray of bool or None
        ``classifier.predict(X) == classes_[1]``.
    violations : dict or None
        Demonstration name -> violated MAP clause keys, for every demonstration predicted
        unacceptable.
    labels : ndarray of bool or None
        ``y == classes_[1]``.
    confusion_matrix : pandas.DataFrame or None
        Rows: label (acceptable, unacceptable); columns: MAP specification's verdict.
    f1, f1_weighted : float or None
        F1 of the MAP specification for the acceptable class, and the mean of both classes'
        F1 weighted by support (the paper's LFE score).
    vote_f1_weighted : float or None
        The same weighted F1 for the classifier's posterior vote (``predict``).
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)
        self._pngs = None

    def __repr__(self):
        return (f"SpecificationReport(title={self.title!r}, map={self.ltl!r}, "
                f"n_clauses={len(self.clauses)})")

    # ------------------------------------------------------------------ sentences
    @property
    def sentences(self):
        """One plain-English sentence per MAP clause."""
        return list(self.clauses["sentence"])

    # ------------------------------------------------------------------ figures
    def figures(self):
        """The report's figures as PNG bytes, by name (rendered once, then cached).

        Names: ``clause_marginals``, ``order_dag`` (when the MAP has orders),
        ``satisfaction`` (with demonstrations and at least one MAP clause),
        ``confusion_matrix`` (with labels).
        """
        if self._pngs is None:
            self._pngs = self._render_figures()
        return dict(self._pngs)

    def _marginal_rows(self):
        m = self.clause_marginals
        in_map = set(self.clauses.index)
        keys = list(m.index)
        if len(keys) > 60:  # keep the chart readable: drop near-impossible clauses
            keys = [k for k in keys if m[k] >= 0.01 or k in in_map]
        return keys, [m[k] for k in keys], [k in in_map for k in keys]

    def _render_figures(self):
        conds = self.specification.conditions
        pngs = {}
        keys, values, in_map = self._marginal_rows()
        if keys:
            pngs["clause_marginals"] = figures.marginals_png(
                [_short_label(k) for k in keys], values, in_map)
        if self.order_edges:
            nodes = sorted({x for e in self.order_edges for x in e}, key=_sort_key)
            labels = {}
            for v in nodes:
                text = str(v)
                if v in self.descriptions:
                    text += "\n" + figures.wrap_label(self.descriptions[v])
                labels[v] = text
            probs = {(a, b): float(self.clause_marginals[("U", a, b)])
                     for a, b in self.order_edges}
            pngs["order_dag"] = figures.order_dag_png(nodes, self.order_edges, labels, probs)
        if self.clause_states is not None and len(self.clauses):
            states = self.clause_states.to_numpy()
            overall = self.map_satisfied.astype(int)[None, :]
            rows = [clause_specification(k, conds).to_ltl() for k in self.clauses.index]
            cols = []
            for j, name in enumerate(self.demo_names):
                label = name
                if self.labels is not None:
                    label += f"\ny={int(self.labels[j])}"
                cols.append(label)
            colors = ["#b2182b" if not ok else "black" for ok in self.predicted_acceptable]
            pngs["satisfaction"] = figures.satisfaction_png(
                np.vstack([states, overall]), rows + ["MAP specification"], cols, colors)
        if self.confusion_matrix is not None:
            pngs["confusion_matrix"] = figures.confusion_matrix_png(
                self.confusion_matrix.to_numpy(), ["acceptable", "unacceptable"])
        return pngs

    # ------------------------------------------------------------------ document
    def _document(self):
        doc = _Doc()
        pngs = self.figures()
        doc.add("h", 1, self.title)
        self._section_specification(doc)
        self._section_posterior(doc, pngs)
        self._section_orders(doc, pngs)
        if self.clause_states is not None:
            self._section_demonstrations(doc, pngs)
        if self.confusion_matrix is not None:
            self._section_labels(doc, pngs)
        self._section_propositions(doc)
        return doc, pngs

    def _section_specification(self, doc):
        doc.add("h", 2, "MAP specification")
        info = self.inference
        doc.add("p", f"The most probable specification (posterior probability "
                     f"{self.map_probability:.3f}) has {len(self.clauses)} clause"
                     f"{'' if len(self.clauses) == 1 else 's'}; a demonstration is acceptable "
                     f"when it satisfies all of them. Inferred with the {info['prior']} prior "
                     f"and the {info['likelihood']} likelihood ({info['method']} inference).")
        doc.add("pre", self.ltl)
        doc.add("math", self.ltl_latex)
        if not len(self.clauses):
            doc.add("p", "The MAP specification is 'true': it accepts every demonstration.")
            return
        groups = (("global", "Always (global clauses)"), ("eventual", "Eventually"),
                  ("order", "Ordering"))
        for kind, heading in groups:
            rows = self.clauses[self.clauses["kind"] == kind]
            if len(rows):
                doc.add("h", 3, heading)
                doc.add("ul", [[f"{s} ", _Code(ltl), f" (p = {p:.2f})"]
                               for s, ltl, p in zip(rows["sentence"], rows["ltl"],
                                                    rows["inclusion_probability"])])
        doc.add("p", "\"A before B\" means that A does happen, and B does not happen at an "
                     "earlier step than A. Conditions are read at the first step. p is the "
                     "posterior probability that the clause belongs to the specification.")

    def _section_posterior(self, doc, pngs):
        doc.add("h", 2, "Posterior")
        info = self.inference
        text = (f"{self.n_unique_specifications} unique specifications; entropy "
                f"{self.entropy:.3f} nats ({self.entropy / np.log(2):.3f} bits).")
        if info.get("dropped_mass"):
            text += f" Posterior mass left out of the list: {info['dropped_mass']:.2g}."
        if info.get("rhat") is not None:
            text += f" MCMC split-R-hat of the log posterior: {info['rhat']:.3f}."
        doc.add("p", text)
        doc.add("table", ["rank", "probability", "difference from the MAP", "specification"],
                [[str(r), f"{p:.4f}", _Code(diff) if diff else "(MAP)", _Code(ltl)]
                 for r, p, diff, ltl in zip(self.top.index, self.top["probability"],
                                            self.top["difference"], self.top["ltl"])])
        if "clause_marginals" in pngs:
            doc.add("h", 3, "Clause inclusion probabilities")
            doc.add("figure", "clause_marginals",
                    "Posterior probability that each candidate clause belongs to the "
                    "specification (blue: in the MAP specification).")

    def _section_orders(self, doc, pngs):
        doc.add("h", 2, "Ordering constraints")
        if "order_dag" not in pngs:
            doc.add("p", "The MAP specification has no ordering constraints.")
            return
        doc.add("p", "An arrow from A to B: A must happen before B (implied orders, A before "
                     "C when A before B before C, are not drawn).")
        doc.add("figure", "order_dag", "Ordering constraints of the MAP specification.")

    def _section_demonstrations(self, doc, pngs):
        n = len(self.demo_names)
        n_bad = int((~self.predicted_acceptable).sum())
        doc.add("h", 2, "Demonstrations")
        doc.add("p", f"{n} demonstration{'' if n == 1 else 's'}, "
                     f"{int(self.map_satisfied.sum())} satisfy the MAP specification; the "
                     f"classifier (posterior vote) predicts {n_bad} unacceptable.")
        if "satisfaction" in pngs:
            doc.add("figure", "satisfaction",
                    "Clause-by-demonstration satisfaction of the MAP specification "
                    "(last row: all clauses together).")
        if not n_bad:
            return
        doc.add("h", 3, "Why demonstrations are predicted unacceptable")
        sentence = dict(zip(self.clauses.index, self.clauses["sentence"]))
        ltl = dict(zip(self.clauses.index, self.clauses["ltl"]))
        rows = []
        for j, name in enumerate(self.demo_names):
            if self.predicted_acceptable[j]:
                continue
            keys = self.violations[name]
            if keys:
                why = [x for k in keys for x in (f"{sentence[k]} ", _Code(ltl[k]), "; ")][:-1]
            else:
                why = ("none: it satisfies the MAP specification but less than half of the "
                       "posterior mass")
            row = [name, f"{self.proba[j]:.3f}"]
            if self.labels is not None:
                row.append("acceptable" if self.labels[j] else "unacceptable")
            rows.append(row + [why])
        header = ["demonstration", "P(acceptable)"]
        header += ["label"] if self.labels is not None else []
        doc.add("table", header + ["violated clauses"], rows)

    def _section_labels(self, doc, pngs):
        doc.add("h", 2, "Agreement with the labels")
        cm = self.confusion_matrix.to_numpy()
        doc.add("p", f"MAP specification: F1 (acceptable) = {self.f1:.3f}, weighted F1 = "
                     f"{self.f1_weighted:.3f}. Posterior vote (predict): weighted F1 = "
                     f"{self.vote_f1_weighted:.3f}.")
        doc.add("table", ["label", "MAP says acceptable", "MAP says unacceptable"],
                [["acceptable", str(cm[0, 0]), str(cm[0, 1])],
                 ["unacceptable", str(cm[1, 0]), str(cm[1, 1])]])
        doc.add("figure", "confusion_matrix", "Confusion matrix of the MAP specification.")

    def _section_propositions(self, doc):
        doc.add("h", 2, "Propositions")
        rows = []
        for name, role in self.roles_table:
            rows.append([_Code(str(name)), role, self.descriptions.get(name, "")])
        doc.add("table", ["proposition", "role", "description"], rows)

    # ------------------------------------------------------------------ outputs
    def markdown(self, figure_dir="."):
        """The report as Markdown text, figures referenced as ``figure_dir/<name>.png``."""
        doc, pngs = self._document()
        prefix = str(figure_dir).rstrip("/")
        files = {name: f"{prefix}/{name}.png" if prefix not in ("", ".") else f"{name}.png"
                 for name in pngs}
        return _render_markdown(doc, files)

    def to_markdown(self, directory):
        """Write ``report.md`` and its PNG figures into ``directory`` (created if needed).

        Returns
        -------
        pathlib.Path
            The path of ``report.md``.
        """
        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        doc, pngs = self._document()
        for name, data in pngs.items():
            (directory / f"{name}.png").write_bytes(data)
        path = directory / "report.md"
        path.write_text(_render_markdown(doc, {n: f"{n}.png" for n in pngs}), encoding="utf-8")
        return path

    def html(self):
        """The report as one self-contained HTML document (figures embedded as base64 PNG)."""
        doc, pngs = self._document()
        return (
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
            f"<title>{html.escape(self.title)}</title>\n<style>{_CSS}</style>\n</head>\n"
            f"<body>\n{_render_html_body(doc, pngs)}\n</body>\n</html>\n"
        )

    def to_html(self, path):
        """Write the self-contained HTML report to ``path``; returns it as a ``Path``."""
        path = Path(path)
        if path.parent != Path(""):
            path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(self.html(), encoding="utf-8")
        return path

    def _repr_html_(self):
        doc, pngs = self._document()
        return f"<style>{_CSS}</style>\n{_render_html_body(doc, pngs)}"


def _difference(spec, reference):
    """Clauses added to (+) and removed from (-) ``reference`` to obtain ``spec``."""
    mine, ref = spec.clauses(), reference.clauses()
    added = [f"+ {clause_specification(k, spec.conditions).to_ltl()}"
             for k in ordered_clauses(spec) if k not in ref]
    removed = [f"- {clause_specification(k, reference.conditions).to_ltl()}"
               for k in ordered_clauses(reference) if k not in mine]
    return "; ".join(added + removed)


def _short_label(key):
    if key[0] == "G":
        return f"G({key[1]})"
    if key[0] == "F":
        return f"F({key[1]})"
    return f"{key[1]} before {key[2]}"


# ---------------------------------------------------------------------------- explain
def explain(classifier, X=None, y=None, descriptions=None, top_k=5, *, title=None,
            demo_names=None):
    """Explain a fitted classifier: its MAP specification, posterior and verdicts.

    Parameters
    ----------
    classifier : BSIClassifier
        A fitted classifier.
    X : demonstrations, default=None
        Any format accepted by ``classifier.predict``. Adds the clause-by-demonstration
        satisfaction heatmap and, for every demonstration the classifier predicts
        unacceptable, the MAP clauses it violates.
    y : array-like of shape (n_demos,), default=None
        Labels of ``X`` (values of ``classifier.classes_``). Adds the MAP specification's
        confusion matrix and F1.
    descriptions : dict, default=None
        Proposition -> short phrase in the present tense (``{"omega_3": "POI 3 is
        visited"}``), used in the sentences (see :func:`clause_sentence`) and the figures.
        Propositions without a description read ``"<name> holds"``.
    top_k : int, default=5
        Number of most probable specifications listed.
    title : str, default=None
        Report title; ``"BSI specification report"`` when omitted.
    demo_names : sequence of str, default=None
        A name per demonstration of ``X``; their indices when omitted.

    Returns
    -------
    SpecificationReport

    Examples
    --------
    >>> import numpy as np
    >>> from bsi_sklearn import BSIClassifier
    >>> X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
    ...      np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]]),
    ...      np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
    >>> clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2]).fit(X, [1, 1, 0])
    >>> report = explain(clf, X, [1, 1, 0],
    ...                  descriptions={0: "the robot is safe", 1: "the part is picked",
    ...                                2: "the part is placed"})
    >>> print(report.ltl)
    G(0) & F(1) & F(2) & (!2 U 1)
    >>> for sentence in report.sentences:
    ...     print(sentence)
    Always, the robot is safe.
    Eventually, the part is picked.
    Eventually, the part is placed.
    The part is picked before the part is placed.
    >>> report.violations
    {'2': [('U', 1, 2)]}
    >>> report.f1_weighted
    1.0
    """
    check_is_fitted(classifier, ["posterior_", "map_specification_"])
    posterior = classifier.posterior_
    roles = posterior.roles
    names = list(roles.names)
    descriptions = _check_descriptions(descriptions, names)
    if isinstance(top_k, bool) or not isinstance(top_k, numbers.Integral) or top_k < 1:
        raise ValueError(f"top_k must be a positive integer, got {top_k!r}")
    if title is None:
        title = "BSI specification report"
    if not isinstance(title, str):
        raise ValueError(f"title must be a string, got {type(title).__name__}")
    if y is not None and X is None:
        raise ValueError("y was given without X: labels need their demonstrations")

    spec = classifier.map_specification_
    conds = spec.conditions
    keys = ordered_clauses(spec)
    marginals = posterior.clause_marginals()
    marginal = dict(zip(marginals.index, marginals.to_numpy()))
    clauses = pd.DataFrame(
        {
            "kind": [_KINDS[k[0]] for k in keys],
            "ltl": [clause_specification(k, conds).to_ltl() for k in keys],
            "latex": [clause_specification(k, conds).to_ltl(latex=True) for k in keys],
            "sentence": [clause_sentence(k, conds, descriptions) for k in keys],
            "inclusion_probability": [float(marginal.get(k, np.nan)) for k in keys],
        },
        index=pd.Index(keys, tupleize_cols=False, name="clause", dtype=object),
    )
    frame = posterior.to_frame(k=top_k)
    top = pd.DataFrame(
        {"probability": frame["probability"].to_numpy(), "ltl": frame["ltl"].to_numpy(),
         "n_clauses": (frame["n_globals"] + frame["n_eventuals"] + frame["n_orders"]).to_numpy(),
         "difference": [_difference(s, spec) for s in frame["specification"]]},
        index=pd.RangeIndex(1, len(frame) + 1, name="rank"),
    )
    diagnostics = getattr(classifier, "mcmc_diagnostics_", None)
    inference = {
        "method": getattr(classifier, "inference_", "unknown"),
        "prior": classifier.prior,
        "likelihood": classifier.likelihood,
        "dropped_mass": float(posterior.dropped_mass),
        "rhat": None if not diagnostics else float(diagnostics["rhat"]),
    }
    fields = dict(
        title=title, specification=spec, ltl=spec.to_ltl(), ltl_latex=spec.to_ltl(latex=True),
        clauses=clauses, descriptions=descriptions, top=top,
        map_probability=float(posterior.probabilities[0]), entropy=posterior.entropy(),
        n_unique_specifications=len(posterior), clause_marginals=marginals,
        order_edges=_transitive_reduction(spec.orders), inference=inference,
        roles_table=_roles_table(roles),
        demo_names=None, clause_states=None, map_satisfied=None, proba=None,
        predicted_acceptable=None, violations=None, labels=None, confusion_matrix=None,
        f1=None, f1_weighted=None, vote_f1_weighted=None,
    )
    if X is not None:
        fields.update(_demonstration_fields(classifier, X, y, keys, conds, demo_names))
    return SpecificationReport(**fields)


def _roles_table(roles):
    glob = set(roles.global_names())
    subs = set(roles.subtask_names())
    cond_of = {}
    for w, c in roles.condition_names().items():
        cond_of.setdefault(c, []).append(w)
    rows = []
    for name in roles.names:
        parts = []
        if name in glob:
            parts.append("global candidate")
        if name in subs:
            parts.append("subtask")
        if name in cond_of:
            parts.append("condition of " + ", ".join(str(w) for w in cond_of[name]))
        rows.append((name, "; ".join(parts) or "unused"))
    return rows


def _demonstration_fields(classifier, X, y, keys, conds, demo_names):
    traces = check_traces(X, binarize=classifier.binarize, estimator_name="explain")
    check_consistent_traces(traces, classifier.n_features_in_,
                            getattr(classifier, "feature_names_in_", None), "explain")
    n = traces.n_demos
    if demo_names is None:
        demo_names = [str(i) for i in range(n)]
    else:
        demo_names = [str(d) for d in demo_names]
        if len(demo_names) != n:
            raise ValueError(f"demo_names has {len(demo_names)} entries for {n} demonstrations")
        if len(set(demo_names)) != n:
            raise ValueError("demo_names must be unique")
    names = list(classifier.posterior_.roles.names)
    col = {p: i for i, p in enumerate(names)}
    single = [clause_specification(k, conds) for k in keys]
    states = np.zeros((len(keys), n), dtype=int)
    for i in range(n):
        trace = traces.trace(i)
        for r, (k, s) in enumerate(zip(keys, single)):
            if not s.satisfied_by(trace, names):
                states[r, i] = 0
            else:
                c = _clause_condition(k, conds)
                states[r, i] = 2 if c is not None and not trace[0, col[c]] else 1
    map_satisfied = (states > 0).all(axis=0)
    proba = classifier.posterior_.predict_proba(traces)[:, 1]
    predicted_acceptable = proba >= 0.5  # classifier.predict's rule
    violations = {demo_names[i]: [k for r, k in enumerate(keys) if states[r, i] == 0]
                  for i in range(n) if not predicted_acceptable[i]}
    fields = dict(
        demo_names=demo_names,
        clause_states=pd.DataFrame(states, index=pd.Index(keys, tupleize_cols=False,
                                                          name="clause", dtype=object),
                                   columns=pd.Index(demo_names, name="demonstration")),
        map_satisfied=map_satisfied, proba=proba, predicted_acceptable=predicted_acceptable,
        violations=violations,
    )
    if y is not None:
        labels = _check_y(y, n, classifier.classes_)
        cm = confusion_matrix(labels, map_satisfied, labels=[True, False])
        fields.update(
            labels=labels,
            confusion_matrix=pd.DataFrame(
                cm, index=pd.Index(["acceptable", "unacceptable"], name="label"),
                columns=pd.Index(["acceptable", "unacceptable"], name="MAP specification")),
            f1=float(f1_score(labels, map_satisfied, pos_label=True, zero_division=0.0)),
            f1_weighted=float(f1_score(labels, map_satisfied, average="weighted",
                                       labels=[True, False], zero_division=0.0)),
            vote_f1_weighted=float(f1_score(labels, predicted_acceptable, average="weighted",
                                            labels=[True, False], zero_division=0.0)),
        )
    return fields


def _check_y(y, n, classes):
    arr = np.asarray(y)
    if arr.ndim != 1 or len(arr) != n:
        raise ValueError(f"y must be 1-D with one label per demonstration ({n}), got shape "
                         f"{arr.shape}")
    known = np.asarray(classes).tolist()
    for i, v in enumerate(arr.tolist()):
        if not any(v == c for c in known):
            raise ValueError(f"y[{i}] = {v!r} is not one of the classifier's classes {known}")
    return np.array([v == classes[1] for v in arr], dtype=bool)
