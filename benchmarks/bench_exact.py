"""Exact enumeration time vs number of hypotheses, for the three priors."""

import matplotlib.pyplot as plt
import numpy as np
from _common import Section, fmt_n, fmt_s, md_table, problem_roles, save_figure, time_call
from _data import make_demos

from bsi_sklearn import BSIClassifier
from bsi_sklearn.model.priors import count_hypotheses

#: (prior, globals, subtasks), from a few hundred to about ten million hypotheses.
GRID = [
    ("sets_of_chains", 2, 3), ("sets_of_chains", 3, 4), ("sets_of_chains", 5, 4),
    ("sets_of_chains", 3, 5), ("sets_of_chains", 5, 5), ("sets_of_chains", 4, 6),
    ("sets_of_chains", 5, 6),
    ("forest", 2, 3), ("forest", 5, 4), ("forest", 5, 5), ("forest", 2, 6),
    ("linear_chain", 2, 3), ("linear_chain", 5, 5), ("linear_chain", 5, 6),
    ("linear_chain", 3, 7),
]
QUICK_GRID = [("sets_of_chains", 2, 3), ("sets_of_chains", 3, 4), ("forest", 3, 4),
              ("linear_chain", 3, 4)]
LIMIT = 20_000_000


def run(cfg):
    sec = Section("exact", "Exact enumeration time vs number of hypotheses")
    n_demos = cfg.pick(50, 20)
    sec.add(f"`BSIClassifier(inference='exact')` on {n_demos} demonstrations of about 200 "
            "steps (`benchmarks/_data.make_demos`, 5 of them negative), full `fit` wall time. "
            "The enumeration sums interchangeable parts into groups and skips, with a bound, "
            "the order structures and pairs of groups that cannot add 1e-17 of the evidence "
            "(`bsi_sklearn/exact.py`), so its time follows the data more than the support: "
            "`hypotheses/s` is an effective rate, support size over time.")
    rows, data = [], {"runs": []}
    for prior, n_g, n in cfg.pick(GRID, QUICK_GRID):
        X, y, roles = make_demos(n_demos - 5, 200, n_subtasks=n, n_globals=n_g, n_negative=5,
                                 seed=5)
        n_hyp = count_hypotheses(prior, n_g, n)
        clf = BSIClassifier(**problem_roles(roles), prior=prior, likelihood="cb",
                            inference="exact",
                            max_exact_hypotheses=LIMIT)
        wall, cpu, _, _ = time_call(lambda c=clf, X=X, y=y: c.fit(X, y),
                                    1 if n_hyp > 2_000_000 else cfg.pick(3, 1))
        data["runs"].append({"prior": prior, "n_globals": n_g, "n_subtasks": n,
                             "hypotheses": n_hyp, "wall_s": wall, "cpu_s": cpu,
                             "kept": len(clf.posterior_)})
        rows.append([prior, n_g, n, fmt_n(n_hyp), fmt_s(wall), fmt_s(cpu),
                     fmt_n(n_hyp / wall), fmt_n(len(clf.posterior_))])
    sec.add(md_table(["prior", "globals", "subtasks", "hypotheses", "wall", "cpu",
                      "hypotheses/s", "kept (tol=1e-9)"], rows))
    big = [r for r in data["runs"] if r["hypotheses"] >= 100_000]
    if big:
        rate = float(np.median([r["hypotheses"] / r["wall_s"] for r in big]))
        data["hypotheses_per_s"] = rate
        sec.add(f"From 100,000 hypotheses up: about {fmt_n(rate)} hypotheses per second "
                "(median effective rate). `inference='auto'` enumerates whenever the work "
                "fits a budget of about a second, or of what its MCMC fallback would cost "
                "where that is more (docs/auto-budget.md), whatever the support's size, and "
                "samples beyond it; see the exact_limit and exact_noroles sections.")
    fig, ax = plt.subplots(figsize=(6, 4))
    for prior, marker in (("linear_chain", "^"), ("sets_of_chains", "o"), ("forest", "s")):
        pts = sorted((r["hypotheses"], r["wall_s"]) for r in data["runs"] if r["prior"] == prior)
        if pts:
            ax.loglog(*zip(*pts), marker + "-", label=prior)
    ax.set_xlabel("hypotheses in the support")
    ax.set_ylabel("exact fit, seconds (median)")
    ax.set_title(f"Exact enumeration ({n_demos} demos)")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    sec.add(save_figure(fig, cfg, "exact_vs_hypotheses"))
    data["targets"] = []
    sec.data = data
    return sec
