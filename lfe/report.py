"""``bsi-lfe report``: interpretability reports of the MAP specification per mission objective."""

from __future__ import annotations

import html
from numbers import Integral
from pathlib import Path

from bsi_sklearn.classifier import BSIClassifier
from bsi_sklearn.param_validation import Interval, check_options
from bsi_sklearn.report import explain
from lfe._settings import REPORT_QUICK
from lfe.annotate import MISSION_OBJECTIVES
from lfe.dataset import load_lfe_dataset, make_lfe_dataset
from lfe.extractor import LFEPropositionExtractor
from lfe.propositions import PROPOSITION_DESCRIPTIONS

__all__ = ["OBJECTIVE_TITLES", "explain_objectives", "run", "write_reports"]

#: The mission objectives as the commander briefs them (paper, section on LFE).
OBJECTIVE_TITLES = {
    "MO1": "Gain and maintain air superiority",
    "MO2": "Destroy the assigned target within the time-on-target window",
    "MO3": "Friendly attrition does not exceed 25%",
}


def explain_objectives(dataset=None, *, objectives=MISSION_OBJECTIVES, propositions="paper",
                       prior="sets_of_chains", likelihood="cb", inference="auto",
                       n_samples=10_000, n_chains=4, burn_in=100, random_state=0,
                       n_jobs=None):
    """Fit BSI on a whole LFE dataset per mission objective and explain each fit.

    Parameters
    ----------
    dataset : LFEDataset, default=None
        The scenarios and the commander's labels; the built-in dataset
        (:func:`lfe.load_lfe_dataset`) when omitted.
    objectives : sequence of str, default=("MO1", "MO2", "MO3")
        Columns of ``dataset.labels`` to explain.
    propositions : {"paper", "extended"}, default="paper"
        Proposition set of :class:`lfe.LFEPropositionExtractor`; its roles are the
        classifier's.
    prior, likelihood, inference, n_samples, n_chains, burn_in, random_state, n_jobs
        :class:`bsi_sklearn.BSIClassifier` parameters. ``inference="auto"`` enumerates the
        posterior exactly up to 20 million hypotheses (the paper's proposition set under
        Prior 2 is exact), else samples it.

    Returns
    -------
    reports : dict
        Objective -> :class:`bsi_sklearn.report.SpecificationReport`, built with the
        training scenarios and labels (heatmap, violated clauses, confusion matrix) and the
        propositions described in the commander's words
        (:data:`lfe.PROPOSITION_DESCRIPTIONS`).

    Examples
    --------
    >>> from lfe import make_lfe_dataset
    >>> ds = make_lfe_dataset(n_scenarios=4, random_state=0)
    >>> reports = explain_objectives(ds, objectives=["MO3"], inference="mcmc", n_samples=200,
    ...                              n_chains=1)
    >>> reports["MO3"].title
    'MO3: Friendly attrition does not exceed 25%'
    """
    if dataset is None:
        dataset = load_lfe_dataset()
    if isinstance(objectives, str):
        objectives = [objectives]
    for objective in objectives:
        if objective not in dataset.labels.columns:
            raise ValueError(
                f"unknown objective {objective!r}; the dataset has {list(dataset.labels.columns)}"
            )
    extractor = LFEPropositionExtractor(propositions=propositions).fit(dataset.scenarios)
    X = extractor.transform(dataset.scenarios)
    names = set(extractor.get_feature_names_out())
    descriptions = {p: d for p, d in PROPOSITION_DESCRIPTIONS.items() if p in names}
    reports = {}
    for objective in objectives:
        y = dataset.labels[objective].to_numpy()
        clf = BSIClassifier(
            prior=prior, likelihood=likelihood, inference=inference, n_samples=n_samples,
            n_chains=n_chains, burn_in=burn_in,
            global_candidates=extractor.global_candidates_, subtasks=extractor.subtasks_,
            conditions=extractor.conditions_, random_state=random_state, n_jobs=n_jobs,
        )
        clf.fit(X, y)  # a ConvergenceWarning, if MCMC ran and did not converge, reaches the user
        title = f"{objective}: {OBJECTIVE_TITLES[objective]}" if objective in OBJECTIVE_TITLES \
            else objective
        reports[objective] = explain(clf, X, y, descriptions=descriptions, title=title,
                                     demo_names=dataset.scenario_ids)
    return reports


def write_reports(reports, out):
    """Write every report (``<out>/<objective>/report.{html,md}`` + PNG) and ``index.html``.

    Parameters
    ----------
    reports : dict
        Objective -> :class:`bsi_sklearn.report.SpecificationReport`.
    out : str or Path
        Output directory (created if needed).

    Returns
    -------
    pathlib.Path
        The path of ``index.html``.

    Raises
    ------
    OSError
        Naming the file that could not be written; the files are written all or none.
    """
    from bsi_sklearn.io import write_files_atomic

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rows, files = [], {}
    for objective, report in reports.items():
        folder = out / objective
        folder.mkdir(exist_ok=True)
        files.update(report.markdown_files(folder))
        files[folder / "report.html"] = report.html()
        rows.append(_index_row(objective, report))
    index = out / "index.html"
    files[index] = _index_html(rows)
    # all or nothing: a failed write (read-only folder, full disk) leaves the previous
    # reports whole, with no temporary file
    write_files_atomic(files)
    return index


def _index_row(objective, report):
    e = html.escape
    # the MAP as the report shows it: implied orders left out, untested clauses marked
    shown = report.clauses[~report.clauses["implied"]]
    sentences = "".join(f"<li>{e(s)}{' (untested)' if vacuous else ''}</li>"
                        for s, vacuous in zip(shown["sentence"], shown["vacuous"])) or \
        "<li>No constraint: every mission is acceptable.</li>"
    f1 = "" if report.f1_weighted is None else f"{report.f1_weighted:.3f}"
    return (
        f'<tr><td><a href="{e(objective)}/report.html">{e(report.title)}</a><br/>'
        f'<small><a href="{e(objective)}/report.md">Markdown</a></small></td>'
        f"<td><code>{e(report.readable)}</code><ul>{sentences}</ul></td>"
        f"<td>{report.map_probability:.3f}</td><td>{report.n_unique_specifications}</td>"
        f"<td>{f1}</td></tr>"
    )


def _index_html(rows):
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
        "<title>LFE mission objectives: what BSI learned</title>\n<style>\n"
        "body { font-family: -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif; "
        "max-width: 75em; line-height: 1.4; }\n"
        "table { border-collapse: collapse; } td, th { border: 1px solid #ccc; "
        "padding: 0.3em 0.6em; vertical-align: top; text-align: left; }\n"
        "th { background: #f0f3f7; } code { font-size: 0.85em; }\n</style>\n</head>\n<body>\n"
        "<h1>LFE mission objectives: what BSI learned</h1>\n"
        "<p>One Bayesian Specification Inference model per mission objective, fitted on every "
        "scenario of the dataset with the commander's verdicts. Each report explains the most "
        "probable (MAP) specification clause by clause.</p>\n"
        "<table><thead><tr><th>objective</th><th>MAP specification</th>"
        "<th>P(MAP)</th><th>unique specifications</th><th>weighted F1 (MAP, training)</th>"
        "</tr></thead>\n<tbody>\n" + "\n".join(rows) + "\n</tbody></table>\n</body>\n</html>\n"
    )


_OPTION_CONSTRAINTS = {
    "n_samples": BSIClassifier._parameter_constraints["n_samples"],
    "seed": [Interval(Integral, 0, 2**32 - 1, closed="both")],
    "n_jobs": BSIClassifier._parameter_constraints["n_jobs"],
}


def run(args):
    """Fit, explain and write the reports; print a one-line summary per objective."""
    check_options(args, _OPTION_CONSTRAINTS)
    if args.dataset is None and args.quick:
        dataset = make_lfe_dataset(n_scenarios=REPORT_QUICK["n_scenarios"],
                                   random_state=args.seed)
    else:
        dataset = load_lfe_dataset(args.dataset)
    if args.quick:
        # auto: exact whenever its work budget allows (milliseconds on the LFE template)
        sampling = dict(inference="auto", n_samples=REPORT_QUICK["n_samples"],
                        n_chains=REPORT_QUICK["n_chains"], burn_in=REPORT_QUICK["burn_in"])
    else:
        sampling = dict(inference=args.inference, n_samples=args.n_samples)
    reports = explain_objectives(
        dataset, objectives=args.objectives, propositions=args.propositions, prior=args.prior,
        likelihood=args.likelihood, random_state=args.seed, n_jobs=args.n_jobs, **sampling,
    )
    index = write_reports(reports, args.out)
    for objective, report in reports.items():
        print(f"{objective}: P(MAP)={report.map_probability:.3f}  "
              f"weighted F1={report.f1_weighted:.3f}  {report.readable}")
    print(f"reports written to {index.parent} (open {index})")
    return 0
