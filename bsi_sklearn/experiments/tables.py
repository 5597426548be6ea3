"""Tables of an experiment run (Markdown, summaries by size) and the files that hold them."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from bsi_sklearn.experiments._claims import claims_frame
from bsi_sklearn.experiments._plots import PRIOR_LABELS

__all__ = [
    "SUPERVISED_INTRO",
    "markdown_table",
    "priors_table",
    "summary_table",
    "supervised_table",
    "write_outputs",
]


def _cell(value, floatfmt):
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (float, np.floating)):
        return "" if np.isnan(value) else format(value, floatfmt)
    return str(value).replace("|", "\\|").replace("\n", " ")


def markdown_table(frame, floatfmt=".3g"):
    """A GitHub-flavoured Markdown table of a DataFrame (index dropped).

    Examples
    --------
    >>> import pandas as pd
    >>> print(markdown_table(pd.DataFrame({"a": [1, 2], "b": [0.5, 0.25]})))
    | a | b |
    |---|---|
    | 1 | 0.5 |
    | 2 | 0.25 |
    """
    columns = [str(c) for c in frame.columns]
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join("---" for _ in columns) + "|"]
    for row in frame.itertuples(index=False):
        lines.append("| " + " | ".join(_cell(v, floatfmt) for v in row) + " |")
    return "\n".join(lines)


def summary_table(summary, columns, *, band=True, floatfmt=".2f"):
    """One row per training-set size, one column per (setting, metric), "mean [q25, q75]".

    Parameters
    ----------
    summary : DataFrame
        The output of :func:`bsi_sklearn.experiments._grid.aggregate`.
    columns : sequence of (str, dict, str)
        ``(header, filters, metric)``: the rows of ``summary`` matching ``filters`` (column ->
        value) give the column ``header`` from ``<metric>_mean`` (and its quartiles).
    band : bool, default=True
        Append the interquartile range in brackets.
    floatfmt : str, default=".2f"

    Returns
    -------
    table : DataFrame of str
    """
    sizes = sorted(summary["size"].unique())
    table = pd.DataFrame({"n": sizes})
    for header, filters, metric in columns:
        mask = np.ones(len(summary), dtype=bool)
        for key, value in filters.items():
            mask &= (summary[key] == value).to_numpy()
        rows = summary[mask].set_index("size")
        cells = []
        for n in sizes:
            if n not in rows.index:
                cells.append("")
                continue
            r = rows.loc[n]
            text = format(r[f"{metric}_mean"], floatfmt)
            if band and r[f"{metric}_q25"] != r[f"{metric}_q75"]:
                text += (f" [{format(r[f'{metric}_q25'], floatfmt)}, "
                         f"{format(r[f'{metric}_q75'], floatfmt)}]")
            cells.append(text)
        table[header] = cells
    return table


def write_outputs(out, prefix, *, results, summary, claims, config, sections):
    """Write a run's files into ``out``; returns their paths.

    Files: ``<prefix>_results.csv`` (one row per fit), ``<prefix>_summary.csv`` (mean and
    spread per setting and size), ``<prefix>_claims.csv`` and ``.md`` (the paper's claims
    beside ours), ``<prefix>_config.json`` (sizes, repeats, inference settings, run time) and
    ``<prefix>_report.md`` (claims, configuration and the ``sections``: (title, text) pairs),
    all or none: a failed write raises an ``OSError`` naming the file and changes nothing.
    """
    from bsi_sklearn.io import write_files_atomic

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    contents = {}

    def path(name):
        return out / f"{prefix}_{name}"

    contents[path("results.csv")] = results.to_csv(index=False)
    contents[path("summary.csv")] = summary.to_csv(index=False)
    claims_df = claims_frame(claims)
    contents[path("claims.csv")] = claims_df.to_csv(index=False)
    claims_md = markdown_table(claims_df[["id", "experiment", "paper", "measured", "status"]])
    contents[path("claims.md")] = claims_md + "\n"
    contents[path("config.json")] = json.dumps(config, indent=2, default=str) + "\n"
    lines = [f"# {config['title']}", "", "## The paper's claims and ours", "", claims_md, "",
             "Criteria:", ""]
    lines += [f"- **{c.id}**: {c.criterion}" for c in claims]
    lines += ["", "## Configuration", ""]
    lines += [f"- {key}: {value}" for key, value in config.items() if key != "title"]
    for title, text in sections:
        lines += ["", f"## {title}", "", text]
    contents[path("report.md")] = "\n".join(lines) + "\n"
    # all or nothing: a failed write (read-only folder, full disk) leaves the previous files
    files = write_files_atomic(contents)
    return files


_PRIOR_ORDER = ("linear_chain", "sets_of_chains", "forest")


def priors_table(summary, domain, priors=("sets_of_chains", "forest")):
    """Markdown table of the positive-only CB fits of ``domain``, one column group per prior.

    Columns: expected and best-of-top-5 similarity, expected correct and extra orders, and
    the fractions of fits whose MAP is the ground truth and whose top 5 holds it.
    """
    base = {"domain": domain, "likelihood": "cb", "labels": "positive"}
    cols = []
    for prior in priors:
        f, name = {**base, "prior": prior}, PRIOR_LABELS[prior].replace("Prior ", "P")
        cols += [(f"{name} E[L]", f, "expected_similarity"),
                 (f"{name} best-5 L", f, "best_similarity"),
                 (f"{name} correct", f, "correct_orders"),
                 (f"{name} extra", f, "extra_orders"),
                 (f"{name} MAP=truth", f, "map_is_truth"),
                 (f"{name} truth in top 5", f, "truth_in_top_k")]
    return markdown_table(summary_table(summary, cols))


def supervised_table(summary, domain):
    """Markdown table: expected similarity and held-out accuracy, positive-only vs supervised.

    One column group per (prior, likelihood) run on ``domain``; ``pos`` columns are
    positive-only fits, ``sup`` the same positives plus negatives. Means over the repeats.
    """
    rows = summary[summary["domain"] == domain]
    combos = sorted({(p, lik) for p, lik in zip(rows["prior"], rows["likelihood"])},
                    key=lambda c: (_PRIOR_ORDER.index(c[0]), c[1]))
    cols = []
    for prior, lik in combos:
        name = PRIOR_LABELS[prior].replace("Prior ", "P")
        if len({lk for p, lk in combos if p == prior}) > 1:
            name += f" {lik.upper()}"
        f = {"domain": domain, "prior": prior, "likelihood": lik}
        for what, metric in (("E[L]", "expected_similarity"), ("acc", "test_accuracy")):
            for labels in ("positive", "supervised"):
                cols.append((f"{name} {what} {labels[:3]}", {**f, "labels": labels}, metric))
    return markdown_table(summary_table(summary, cols, band=False))


#: The paragraph that introduces the tables of :func:`supervised_table` in a report.
SUPERVISED_INTRO = (
    "Expected similarity to the ground truth and accuracy on a held-out balanced test set "
    "(positives and negatives), for positive-only fits (`pos`) and for the same positives "
    "plus negatives (`sup`); means over the repeats."
)
