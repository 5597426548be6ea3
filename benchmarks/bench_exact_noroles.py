"""Exact by work, not by support (issue 19): LFE missions, every proposition in every role.

Every one of the 11 propositions is a global candidate and a subtask (``roles="all"``, the
default before issue 20: 3.5e15 hypotheses under Prior 2, CB likelihood). For 18, 36 and 72
missions and each commander's objective (MO1-MO3) ``BSIClassifier(roles="all")`` (every other
parameter at its default) is timed (median of warm fits) beside an uncapped
``inference="exact"`` fit, and their posteriors compared (total variation).

    python benchmarks/run.py --only exact_noroles
"""

from _common import Section, fmt_s, md_table, target, time_call

from bsi_sklearn import BSIClassifier
from bsi_sklearn.inference.diagnostics import total_variation
from lfe import LFEPropositionExtractor, make_lfe_dataset

__all__ = ["run", "CELLS", "TARGET_S"]

#: (missions, make_lfe_dataset seed) of each row.
CELLS = ((18, 2), (36, 3), (72, 1))
#: Issue 19: each no-roles fit exact, in at most a second warm.
TARGET_S = 1.0


def _missions(n, seed):
    ds = make_lfe_dataset(n, random_state=seed)
    return LFEPropositionExtractor().fit_transform(ds.scenarios), ds.labels


def run(cfg):
    sec = Section("exact_noroles", "Exact without roles: LFE missions, the default classifier "
                                   "(issue 19)")
    reps = cfg.pick(5, 1)
    rows, cells = [], []
    for n, seed in cfg.pick(CELLS, CELLS[:1]):
        X, labels = _missions(n, seed)
        for mo in cfg.pick(("MO1", "MO2", "MO3"), ("MO1",)):
            y = labels[mo].to_numpy()
            auto = BSIClassifier(roles="all", likelihood="cb", random_state=0)
            t_auto, _, _, _ = time_call(lambda c=auto, X=X, y=y: c.fit(X, y), reps)
            exact = BSIClassifier(roles="all", likelihood="cb", inference="exact",
                                  max_exact_hypotheses=10**30)
            t_exact, _, _, _ = time_call(lambda c=exact, X=X, y=y: c.fit(X, y), reps)
            tv = total_variation(auto.posterior_, exact.posterior_)
            cells.append({"missions": n, "seed": seed, "objective": mo,
                          "auto": auto.inference_, "auto_fit_s": t_auto,
                          "exact_fit_s": t_exact, "tv": tv, "kept": len(exact.posterior_),
                          "hypotheses": auto.n_hypotheses_})
            rows.append([str(n), mo, auto.inference_, fmt_s(t_auto), fmt_s(t_exact),
                         f"{tv:.2g}", f"{len(exact.posterior_):,}"])
    sec.add("`make_lfe_dataset(n, random_state=seed)` (seeds: 18 missions 2, 36 missions 3, 72 "
            "missions 1), `LFEPropositionExtractor().fit_transform`, labels of one objective; "
            "`roles=\"all\"`: every proposition is a global candidate and a subtask "
            f"({cells[0]['hypotheses']:.2g} hypotheses, Prior 2, CB). `default fit` is "
            "`BSIClassifier(roles=\"all\", likelihood=\"cb\", random_state=0).fit` (whatever "
            "`auto` chose; CB was the default until 2026-12-07), `exact fit` is "
            "`BSIClassifier(roles=\"all\", likelihood=\"cb\", inference=\"exact\", "
            "max_exact_hypotheses=10**30).fit`; median of "
            f"{reps} warm calls each, validation and clause truth included. TV: total variation "
            "between the two posteriors; `kept`: specifications the exact posterior lists.")
    sec.add(md_table(["missions", "objective", "auto chose", "default fit", "exact fit",
                      "TV", "kept"], rows))
    worst = max(c["auto_fit_s"] for c in cells)
    all_exact = all(c["auto"] == "exact" for c in cells)
    worst_tv = max(c["tv"] for c in cells)
    sec.data = {"cells": cells, "targets": [
        target("no roles, 18-72 missions x MO1-MO3: the default classifier exact, in at most "
               "1 s warm", "auto = exact, <= 1 s", f"{'exact' if all_exact else 'not all'}, "
               f"slowest {fmt_s(worst)}", all_exact and worst <= TARGET_S),
        target("the default posterior is the exact one", "TV <= 1e-9", f"{worst_tv:.2g}",
               worst_tv <= 1e-9)]}
    return sec
