"""The tables of ``benchmarks/RESULTS_study.md`` and the README, from a ``bsi-lfe study`` folder.

Reads ``study.csv`` and ``study_paired.csv`` (what the study wrote) and prints Markdown: the
headline counts (significantly better / worse than the best network and than the best of all
baselines, per proposition set and per BSI row) and, per noise rate and proposition set, one
row per objective and size with every BSI row's paired differences. Nothing is computed anew:
the means and intervals are the study's own.

    python benchmarks/study_tables.py benchmarks/study > /tmp/tables.md
    python benchmarks/study_tables.py benchmarks/study --out docs/results/study.md

``--out`` writes the results page the README links to: the headline, the README's compact
tables and every cell's table, in one file.
"""

import argparse
from pathlib import Path

import pandas as pd

__all__ = ["headline", "cell_table", "readme_table", "results_page", "main"]


def _signed(mean, low, high, significant):
    return f"{mean:+.3f} [{low:+.3f}, {high:+.3f}]" + (" *" if significant else "")


def _interval(mean, low, high):
    return f"{mean:.3f} [{low:.3f}, {high:.3f}]"


def _counts(frame):
    better_n = int((frame.significant & (frame["mean"] > 0)).sum())
    worse_n = int((frame.significant & (frame["mean"] < 0)).sum())
    better_b = int((frame.baseline_significant & (frame.baseline_mean > 0)).sum())
    worse_b = int((frame.baseline_significant & (frame.baseline_mean < 0)).sum())
    return better_n, worse_n, better_b, worse_b


def headline(paired):
    """Markdown lines: per proposition set and per BSI row, better / worse counts.

    Parameters
    ----------
    paired : DataFrame
        ``study_paired.csv``.

    Returns
    -------
    lines : list of str
    """
    paired = paired[paired.metric == "f1"]
    lines = ["| propositions | BSI row | comparisons | better / worse than the best network | "
             "better / worse than the best baseline |", "|---|---|---|---|---|"]
    # the paper's propositions first, then the other sets by name
    sets = sorted(set(paired.propositions), key=lambda s: (s != "paper", s))
    for props, group in [("all", paired), *[(s, paired[paired.propositions == s]) for s in sets]]:
        rows = [("every row", group), *group.groupby("bsi", sort=False)]
        for name, frame in rows:
            bn, wn, bb, wb = _counts(frame)
            lines.append(f"| {props} | {name} | {len(frame)} | {bn} / {wn} | {bb} / {wb} |")
    return lines


def cell_table(study, paired, noise, propositions):
    """Markdown lines: per objective and size, the best network and baseline and each BSI row.

    Parameters
    ----------
    study, paired : DataFrame
        ``study.csv`` and ``study_paired.csv``.
    noise : float
    propositions : str

    Returns
    -------
    lines : list of str
    """
    p = paired[(paired.metric == "f1") & (paired.noise == noise)
               & (paired.propositions == propositions)]
    s = study[(study.metric == "f1") & (study.noise == noise)
              & (study.propositions == propositions)].set_index(["classifier", "objective",
                                                                 "n_train"])
    bsi_rows = list(dict.fromkeys(p.bsi))
    head = ["objective", "missions", "best network, F1", "best baseline, F1",
            *[f"{b} − best network / − best baseline" for b in bsi_rows]]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for (objective, n_train), cell in p.groupby(["objective", "n_train"], sort=True):
        first = cell.iloc[0]
        net = s.loc[(first.best_network, objective, n_train)]
        base = s.loc[(first.best_baseline, objective, n_train)]
        parts = [objective, str(n_train),
                 f"{first.best_network}: {_interval(net['mean'], net.ci_low, net.ci_high)}",
                 f"{first.best_baseline}: {_interval(base['mean'], base.ci_low, base.ci_high)}"]
        by_row = cell.set_index("bsi")
        for b in bsi_rows:
            r = by_row.loc[b]
            parts.append(_signed(r["mean"], r.ci_low, r.ci_high, r.significant) + " / "
                         + _signed(r.baseline_mean, r.baseline_ci_low, r.baseline_ci_high,
                                   r.baseline_significant))
        lines.append("| " + " | ".join(parts) + " |")
    return lines


def readme_table(study, paired, noise, propositions):
    """Markdown lines of the README's compact table: BSI (Prior 2) and three differences.

    Per objective and size: the best network and baseline, BSI (Prior 2)'s F1, Prior 2, Prior
    2 with CI and BSI without roles minus the best network, and Prior 2 minus the best
    baseline (``*``: the paired interval excludes 0).
    """
    p = paired[(paired.metric == "f1") & (paired.noise == noise)
               & (paired.propositions == propositions)].set_index(["bsi", "objective",
                                                                   "n_train"])
    s = study[(study.metric == "f1") & (study.noise == noise)
              & (study.propositions == propositions)].set_index(["classifier", "objective",
                                                                 "n_train"])
    head = ["objective", "training missions", "best network, F1", "best baseline, F1",
            "BSI (Prior 2), F1", "Prior 2 − best network", "Prior 2, CI − best network",
            "no roles − best network", "Prior 2 − best baseline"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for objective, n_train in sorted({k[1:] for k in p.index}):
        first = p.loc[("BSI (Prior 2)", objective, n_train)]
        net = s.loc[(first.best_network, objective, n_train)]
        base = s.loc[(first.best_baseline, objective, n_train)]
        bsi = s.loc[("BSI (Prior 2)", objective, n_train)]
        parts = [objective, str(n_train),
                 f"{first.best_network}: {_interval(net['mean'], net.ci_low, net.ci_high)}",
                 f"{first.best_baseline}: {_interval(base['mean'], base.ci_low, base.ci_high)}",
                 _interval(bsi["mean"], bsi.ci_low, bsi.ci_high)]
        for row in ("BSI (Prior 2)", "BSI (Prior 2, CI)", "BSI (no roles)"):
            r = p.loc[(row, objective, n_train)]
            parts.append(_signed(r["mean"], r.ci_low, r.ci_high, r.significant))
        parts.append(_signed(first.baseline_mean, first.baseline_ci_low,
                             first.baseline_ci_high, first.baseline_significant))
        lines.append("| " + " | ".join(parts) + " |")
    return lines


def _props(paired):
    return sorted(set(paired.propositions), key=lambda s: (s != "paper", s))


def _compact(study, paired):
    out = []
    for props in _props(paired):
        out += [f"### Noise 0.04, {props} propositions", "",
                *readme_table(study, paired, 0.04, props), ""]
    return out


def _full(study, paired):
    out = ["## Headline", "", *headline(paired)]
    for props in _props(paired):
        for noise in sorted(set(paired.noise), reverse=True):
            out += ["", f"### Noise {noise:g}, {props} propositions", "",
                    *cell_table(study, paired, noise, props)]
    return out


def results_page(study, paired, folder):
    """The Markdown page of a study's tables (``docs/results/study.md``): every table, one file.

    Parameters
    ----------
    study, paired : DataFrame
        The study's ``study.csv`` and ``study_paired.csv``.
    folder : str or Path
        Where they were read from, named in the page.

    Returns
    -------
    text : str
    """
    return "\n".join([
        "# `bsi-lfe study`: every table", "",
        f"Rendered by `python benchmarks/study_tables.py {Path(folder).as_posix()} --out "
        "docs/results/study.md` from the study's own `study.csv` and `study_paired.csv` "
        "(nothing computed anew). The run, its machine and its warnings: "
        "[`benchmarks/RESULTS_study.md`](../../benchmarks/RESULTS_study.md).", "",
        "Weighted F1, mean [95 % interval over repeats]; `*`: the paired interval excludes 0.",
        "", "## With the default noise (0.04), per proposition set", "",
        *_compact(study, paired), *_full(study, paired), ""])


def main(argv=None):
    """Print the tables of a study folder (the README's with --readme), or write --out."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", type=Path, help="a bsi-lfe study --out folder")
    ap.add_argument("--readme", action="store_true",
                    help="the README's compact tables instead (noise 0.04, per proposition set)")
    ap.add_argument("--out", type=Path, default=None,
                    help="write the results page (every table) to this file instead")
    args = ap.parse_args(argv)
    study = pd.read_csv(args.folder / "study.csv")
    paired = pd.read_csv(args.folder / "study_paired.csv")
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(results_page(study, paired, args.folder), encoding="utf-8")
        print(f"wrote {args.out}")
        return
    print("\n".join(_compact(study, paired) if args.readme else _full(study, paired)))


if __name__ == "__main__":
    main()
