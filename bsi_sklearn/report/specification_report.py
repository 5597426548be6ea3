"""The `SpecificationReport` object: a fitted classifier's explanation, its figures and outputs."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bsi_sklearn.io import write_atomic, write_files_atomic
from bsi_sklearn.report import figures
from bsi_sklearn.report.document import (
    Code,
    Document,
    render_html,
    render_html_fragment,
    render_markdown,
)
from bsi_sklearn.report.wording import (
    _short_label,
    _sort_key,
    unicode_ltl,
)

__all__ = ["SpecificationReport"]


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
        The MAP specification as LTL text and as LaTeX: the full formula, every clause.
    readable : str
        The MAP specification as the report shows it (:meth:`Specification.readable`): the
        orders implied by others left out, the untested clauses set apart.
    negations : None, False or mapping
        Which propositions negate others in the readable texts (``explain``'s argument).
    vacuous_clauses : frozenset of clause keys
        The classifier's ``vacuous_clauses_``: candidate clauses every training
        demonstration satisfies, acceptable or not.
    clauses : pandas.DataFrame
        One row per MAP clause (index: clause keys, reading order): ``kind`` (global,
        eventual, order), ``ltl``, ``latex``, ``readable`` (the clause as
        :meth:`Specification.readable` writes it: what the documents show), ``sentence``,
        ``inclusion_probability``,
        ``implied`` (an order the other orders imply; not listed in the documents) and
        ``vacuous`` (untested: every training demonstration satisfies it; marked).
    descriptions : dict
        Proposition -> phrase used in the sentences.
    top : pandas.DataFrame
        The ``top_k`` most probable specifications, indexed by rank (from 1):
        ``probability``, ``ltl``, ``readable``, ``n_clauses`` and ``difference`` (the clauses
        added, ``+``, and removed, ``-``, relative to the MAP specification; empty for the
        MAP).
    map_probability, entropy : float
        Posterior probability of the MAP specification (its share of the samples, possibly
        0, for a posterior reported by its samples); entropy (nats) of the posterior.
    n_unique_specifications : int
    clause_marginals : pandas.Series
        Posterior inclusion probability of every candidate clause.
    order_edges : list of (a, b)
        Transitive reduction of the MAP orders (the arrows of the DAG figure).
    inference : dict
        How the posterior was obtained: ``method``, ``prior``, ``likelihood``,
        ``dropped_mass``, ``rhat`` and ``max_missed_mass`` (MCMC only; for a posterior
        reported by its samples, ``inclusion_rhat`` instead of ``max_missed_mass``).
    demo_names : list of str or None
        One name per demonstration (``None`` without ``X``).
    clause_states : pandas.DataFrame or None
        MAP clauses x demonstrations: 0 violated, 1 satisfied, 2 satisfied vacuously (the
        clause's condition is false).
    map_satisfied : ndarray of bool or None
        Whether each demonstration satisfies the MAP specification.
    proba : ndarray or None
        The classifier's ``predict_proba(X)[:, 1]``: the posterior predictive probability that
        each demonstration is acceptable or, under ``vote="satisfaction"``, the posterior mass
        of the specifications it satisfies (:attr:`proba_name` says which).
    proba_name : str or None
        ``"P(acceptable)"`` or ``"posterior mass satisfied"``: what :attr:`proba` is.
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
        The same weighted F1 for the classifier's decisions (``predict``).
    """

    def __init__(self, **fields):
        self.__dict__.update(fields)
        self._pngs = None

    def __repr__(self):
        return (f"SpecificationReport(title={self.title!r}, map={self.ltl!r}, "
                f"n_clauses={len(self.clauses)})")

    def _clause_text(self):
        # clause key -> the text the documents show (a report pickled before the readable
        # column existed shows the LTL)
        column = "readable" if "readable" in self.clauses.columns else "ltl"
        return dict(zip(self.clauses.index, self.clauses[column]))

    # ------------------------------------------------------------------ sentences
    @property
    def sentences(self):
        """One plain-English sentence per MAP clause."""
        return list(self.clauses["sentence"])

    def _shown_clauses(self):
        """The MAP clauses the documents list: every one but the implied orders."""
        return self.clauses[~self.clauses["implied"]]

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
            rows = [self._clause_text()[k] for k in self.clauses.index]
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
        doc = Document()
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
        # A posterior reported by its samples lists frequencies: the MAP's may be 0.
        mass = (f"share of the samples {self.map_probability:.3f}: the posterior is too "
                "diffuse to list, and is reported by its samples"
                if info.get("inclusion_rhat") is not None
                else f"posterior probability {self.map_probability:.3f}")
        doc.add("p", f"The most probable specification ({mass}) has {len(self.clauses)} clause"
                     f"{'' if len(self.clauses) == 1 else 's'}; a demonstration is acceptable "
                     f"when it satisfies all of them. Inferred with the {info['prior']} prior "
                     f"and the {info['likelihood']} likelihood ({info['method']} inference).")
        doc.add("pre", self.readable)
        doc.add("formula", unicode_ltl(self.specification, chains=True,
                                       vacuous=self.vacuous_clauses,
                                       negations=getattr(self, "negations", None)))
        if not len(self.clauses):
            doc.add("p", "The MAP specification is 'true': it accepts every demonstration.")
            return
        n_implied, n_vacuous = int(self.clauses["implied"].sum()), int(
            self.clauses["vacuous"][~self.clauses["implied"]].sum())
        if n_implied or n_vacuous:
            notes = []
            if n_implied:
                notes.append(f"{n_implied} order{'' if n_implied == 1 else 's'} implied by the "
                             "others (A before C when A before B before C) left out")
            if n_vacuous:
                notes.append(f"{n_vacuous} untested clause{'' if n_vacuous == 1 else 's'} set "
                             "apart (every training demonstration, acceptable or not, "
                             "satisfies them: the data could not show they are needed)")
            doc.add("p", f"Shown with {' and '.join(notes)}. The full formula:")
            doc.add("pre", " & ".join(self._clause_text().values()))
        groups = (("global", "Always (global clauses)"), ("eventual", "Eventually"),
                  ("order", "Ordering"))
        shown = self._shown_clauses()
        for kind, heading in groups:
            rows = shown[shown["kind"] == kind]
            if len(rows):
                doc.add("h", 3, heading)
                text = self._clause_text()
                doc.add("ul", [[f"{s} ", Code(text[k]),
                                f" (p = {p:.2f}{'; untested' if vacuous else ''})"]
                               for k, s, p, vacuous in zip(
                                   rows.index, rows["sentence"],
                                   rows["inclusion_probability"], rows["vacuous"])])
        doc.add("p", "\"A before B\" means that A does happen, and B does not happen at an "
                     "earlier step than A. Conditions are read at the first step. p is the "
                     "posterior probability that the clause belongs to the specification"
                     + ("; untested: every training demonstration satisfies the clause."
                        if n_vacuous else "."))

    def _section_posterior(self, doc, pngs):
        doc.add("h", 2, "Posterior")
        info = self.inference
        text = (f"{self.n_unique_specifications} unique specifications; entropy "
                f"{self.entropy:.3f} nats ({self.entropy / np.log(2):.3f} bits).")
        if info.get("dropped_mass"):
            text += f" Posterior mass left out of the list: {info['dropped_mass']:.2g}."
        if info.get("rhat") is not None:
            text += f" MCMC split-R-hat of the log posterior: {info['rhat']:.3f}."
        if info.get("max_missed_mass") is not None:
            text += (" Posterior mass the least thorough MCMC chain never reached: "
                     f"{info['max_missed_mass']:.3f} (above 0.05 the chains disagree).")
        if info.get("inclusion_rhat") is not None:
            text += (" Too diffuse to list, the posterior is reported by the MCMC samples: "
                     "the probabilities are their frequencies. Largest split-R-hat of a "
                     f"clause's inclusion across the chains: {info['inclusion_rhat']:.3f} "
                     "(above 1.05 they disagree).")
        doc.add("p", text)
        doc.add("table", ["rank", "probability", "difference from the MAP", "specification"],
                [[str(r), f"{p:.4f}", Code(diff) if diff else "(MAP)", Code(ltl)]
                 for r, p, diff, ltl in zip(self.top.index, self.top["probability"],
                                            self.top["difference"], self.top["readable"])])
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
                     f"classifier (predict) finds {n_bad} unacceptable.")
        if "satisfaction" in pngs:
            doc.add("figure", "satisfaction",
                    "Clause-by-demonstration satisfaction of the MAP specification "
                    "(last row: all clauses together).")
        if not n_bad:
            return
        doc.add("h", 3, "Why demonstrations are predicted unacceptable")
        sentence = dict(zip(self.clauses.index, self.clauses["sentence"]))
        ltl = self._clause_text()
        rows = []
        for j, name in enumerate(self.demo_names):
            if self.predicted_acceptable[j]:
                continue
            keys = self.violations[name]
            if keys:
                why = [x for k in keys for x in (f"{sentence[k]} ", Code(ltl[k]), "; ")][:-1]
            else:
                why = ("none: it satisfies the MAP specification, but the posterior as a "
                       "whole finds it more likely unacceptable")
            row = [name, f"{self.proba[j]:.3f}"]
            if self.labels is not None:
                row.append("acceptable" if self.labels[j] else "unacceptable")
            rows.append(row + [why])
        header = ["demonstration", self.proba_name]
        header += ["label"] if self.labels is not None else []
        doc.add("table", header + ["violated clauses"], rows)

    def _section_labels(self, doc, pngs):
        doc.add("h", 2, "Agreement with the labels")
        cm = self.confusion_matrix.to_numpy()
        doc.add("p", f"MAP specification: F1 (acceptable) = {self.f1:.3f}, weighted F1 = "
                     f"{self.f1_weighted:.3f}. Classifier (predict): weighted F1 = "
                     f"{self.vote_f1_weighted:.3f}.")
        doc.add("table", ["label", "MAP says acceptable", "MAP says unacceptable"],
                [["acceptable", str(cm[0, 0]), str(cm[0, 1])],
                 ["unacceptable", str(cm[1, 0]), str(cm[1, 1])]])
        doc.add("figure", "confusion_matrix", "Confusion matrix of the MAP specification.")

    def _section_propositions(self, doc):
        doc.add("h", 2, "Propositions")
        rows = []
        for name, role in self.roles_table:
            rows.append([Code(str(name)), role, self.descriptions.get(name, "")])
        doc.add("table", ["proposition", "role", "description"], rows)

    # ------------------------------------------------------------------ outputs
    def markdown(self, figure_dir="."):
        """The report as Markdown text, figures referenced as ``figure_dir/<name>.png``."""
        doc, pngs = self._document()
        prefix = str(figure_dir).rstrip("/")
        files = {name: f"{prefix}/{name}.png" if prefix not in ("", ".") else f"{name}.png"
                 for name in pngs}
        return render_markdown(doc, files)

    def to_markdown(self, directory):
        """Write ``report.md`` and its PNG figures into ``directory`` (created if needed).

        The files are written all or none: when one cannot be written (a read-only folder, a
        full disk), the folder keeps its previous files and no temporary file.

        Returns
        -------
        pathlib.Path
            The path of ``report.md``.

        Raises
        ------
        OSError
            Naming the file that could not be written.
        """
        directory = Path(directory)
        directory.mkdir(parents=True, exist_ok=True)
        files = self.markdown_files(directory)
        write_files_atomic(files)
        return directory / "report.md"

    def markdown_files(self, directory):
        """The files :meth:`to_markdown` writes: ``{path: bytes or str}``, ``report.md`` last.

        Parameters
        ----------
        directory : str or path-like

        Returns
        -------
        files : dict
        """
        directory = Path(directory)
        doc, pngs = self._document()
        files = {directory / f"{name}.png": data for name, data in pngs.items()}
        files[directory / "report.md"] = render_markdown(doc, {n: f"{n}.png" for n in pngs})
        return files

    def html(self):
        """The report as one self-contained HTML document (figures embedded as base64 PNG)."""
        doc, pngs = self._document()
        return render_html(doc, pngs, self.title)

    def to_html(self, path):
        """Write the self-contained HTML report to ``path``; returns it as a ``Path``.

        Written in one step: a failed write leaves the previous file, and no temporary file.

        Raises
        ------
        OSError
            Naming ``path`` when it cannot be written.
        """
        path = Path(path)
        if path.parent != Path(""):
            path.parent.mkdir(parents=True, exist_ok=True)
        write_atomic(path, self.html())
        return path

    def _repr_html_(self):
        doc, pngs = self._document()
        return render_html_fragment(doc, pngs)

