"""Coordinate updates (MH steps) per second: per chain, per prior, and two chains in parallel."""

import matplotlib.pyplot as plt
from _common import Section, fmt_n, fmt_s, md_table, problem_roles, save_figure, time_call
from _data import poi_demos
from bench_core import kernel_rate

from bsi_sklearn import BSIClassifier


def run(cfg):
    sec = Section("throughput", "MCMC throughput: coordinate updates (MH steps) per second")
    X, _, roles, source = poi_demos(50, seed=0)
    kw = dict(problem_roles(roles), likelihood="cb")  # as recorded: the paper's
    n_samples = cfg.pick(10_000, 2_000)
    sec.add(f"50 demonstrations from `{source}` (5 globals x 5 subtasks). One *sample* is a "
            "Gibbs sweep that updates every block of every tempered replica once (5 inclusion "
            "bits of tau and 5 re-insertions in the order structure, each with the subtask's "
            "eventual bit); `mcmc_diagnostics_['n_updates']` counts block updates of all "
            "replicas, the unit compared with the single-site MH steps of webppl. The kernel "
            "alone runs one replica (`run_chain` without a ladder).")
    data, rows = {}, []
    for prior in ("linear_chain", "sets_of_chains", "forest"):
        rate, k_sec, upd, n_unique = kernel_rate(X, None, roles, prior=prior,
                                                 n_samples=n_samples, seeds=cfg.pick(5, 1))
        data.setdefault("kernel_updates_per_s", {})[prior] = rate
        rows.append([prior, fmt_n(upd), fmt_s(k_sec), fmt_n(rate),
                     f"{k_sec / upd * 1e9:.0f} ns"])
    sec.add("**One chain, kernel alone** (`run_chain`, thread CPU time, median over seeds):")
    sec.add(md_table(["prior", "updates", "time", "updates/s", "per update"], rows))

    # Chains in parallel, through the estimator.
    n_par = cfg.pick(40_000, 2_000)
    rows, rates = [], {}
    for label, n_chains, n_jobs in [("1 chain", 1, None), ("2 chains, n_jobs=1", 2, 1),
                                    ("2 chains, n_jobs=2", 2, 2)]:
        clf = BSIClassifier(**kw, inference="mcmc", n_chains=n_chains, n_jobs=n_jobs,
                            n_samples=n_par, burn_in=100, random_state=0)
        wall, cpu, _, _ = time_call(lambda c=clf: c.fit(X), cfg.pick(5, 1))
        upd = clf.mcmc_diagnostics_["n_updates"]
        rates[label] = upd / wall
        rows.append([label, fmt_n(upd), fmt_s(wall), fmt_s(cpu), fmt_n(upd / wall),
                     fmt_n(upd / wall / n_chains)])
    speedup = rates["2 chains, n_jobs=2"] / rates["2 chains, n_jobs=1"]
    data["fit_updates_per_s"] = rates
    data["parallel_speedup"] = speedup
    sec.add(f"**Through `fit`** ({n_par:,} samples + 100 burn-in per chain, Prior 2; wall "
            "time of the whole fit):")
    sec.add(md_table(["configuration", "updates", "wall", "cpu", "updates/s (all chains)",
                      "per chain"], rows))
    sec.add(f"Two threads give {speedup:.2f}x the aggregate throughput of one (2 cores, "
            "shared with other work while this ran).")
    fig, ax = plt.subplots(figsize=(6, 3.5))
    labels = list(rates)
    ax.bar(labels, [rates[k] / 1e6 for k in labels], color=["C0", "C1", "C2"])
    ax.set_ylabel("million updates / s")
    ax.set_title("MCMC throughput through fit (Prior 2, 50 demos)")
    ax.grid(True, axis="y", alpha=0.3)
    sec.add(save_figure(fig, cfg, "throughput"))
    data["targets"] = []
    sec.data = data
    return sec
