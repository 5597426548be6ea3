"""``predict_proba`` throughput: demonstrations per second vs batch size and trace length."""

import matplotlib.pyplot as plt
import numpy as np
from _common import Section, fmt_n, fmt_s, md_table, problem_roles, save_figure, time_call
from _data import make_demos

from bsi_sklearn import BSIClassifier


def run(cfg):
    sec = Section("predict", "predict_proba throughput (demonstrations per second)")
    reps = cfg.repeats
    Xtr, ytr, roles = make_demos(5, 200, seed=7)
    kw = dict(problem_roles(roles), likelihood="cb")  # as recorded: the paper's
    models = {
        "MCMC (4 chains x 10,000)": BSIClassifier(**kw, inference="mcmc", random_state=0),
        "exact": BSIClassifier(**kw, inference="exact"),
    }
    for m in models.values():
        m.fit(Xtr, ytr)
    sec.add("Both models are fitted on 5 acceptable demonstrations (the paper's smallest "
            "training set, so the posterior is spread over many specifications; "
            "`benchmarks/_data.make_demos`, 5 globals x 5 subtasks, Prior 2). "
            "`predict_proba` validates the new demonstrations, computes their clause truths "
            "(linear in the time steps) and sums the posterior mass of the specifications "
            "each one satisfies (bit-packed: one AND per specification and 64 "
            "demonstrations). Posterior sizes: "
            + ", ".join(f"{name} {len(m.posterior_):,} specifications"
                        for name, m in models.items()) + ".")
    data = {"posterior_size": {k: len(m.posterior_) for k, m in models.items()}}

    # ------------------------------------------------------------ batch size
    batches = cfg.pick([1, 10, 100, 1_000, 10_000], [1, 10, 100])
    rows, curves = [], {k: [] for k in models}
    for n in batches:
        X, _, _ = make_demos(n, 200, seed=8)
        row = [fmt_n(n)]
        for name, m in models.items():
            wall, _, _, _ = time_call(lambda m=m, X=X: m.predict_proba(X),
                                      min(reps, 3) if n >= 10_000 else reps)
            curves[name].append(n / wall)
            row += [fmt_s(wall), fmt_n(n / wall)]
        rows.append(row)
    data["batch"] = {"n_demos": batches, "demos_per_s": curves}
    sec.add("### vs batch size (traces of about 200 steps)")
    header = ["demos"]
    for name in models:
        header += [f"{name}: time", "demos/s"]
    sec.add(md_table(header, rows))

    # ------------------------------------------------------------ trace length
    lengths = cfg.pick([10, 100, 1_000, 10_000], [10, 100, 1_000])
    n = cfg.pick(1_000, 100)
    rows, len_curves = [], {k: [] for k in models}
    for L in lengths:
        X, _, _ = make_demos(n, L, seed=9)
        steps = sum(len(x) for x in X)
        row = [fmt_n(L), fmt_n(steps)]
        for name, m in models.items():
            wall, _, _, _ = time_call(lambda m=m, X=X: m.predict_proba(X),
                                      min(reps, 3) if steps >= 1_000_000 else reps)
            len_curves[name].append(n / wall)
            row += [fmt_s(wall), fmt_n(n / wall), fmt_n(steps / wall)]
        rows.append(row)
    data["trace_length"] = {"n_demos": n, "length": lengths, "demos_per_s": len_curves}
    sec.add(f"### vs trace length ({n:,} demonstrations per call)")
    header = ["mean length", "time steps"]
    for name in models:
        header += [f"{name}: time", "demos/s", "steps/s"]
    sec.add(md_table(header, rows))
    best = max(max(v) for v in curves.values())
    sec.add(f"Peak throughput {fmt_n(best)} demonstrations/s (200-step traces); per call "
            "there is a fixed cost of input validation, visible at small batches.")

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for name, ys in curves.items():
        ax.loglog(batches, ys, "o-", label=name)
    ax.set_xlabel("demonstrations per predict_proba call")
    ax.set_ylabel("demonstrations / s (median)")
    ax.set_title("Throughput vs batch size (200 steps)")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    for name, ys in len_curves.items():
        ax2.loglog(lengths, ys, "o-", label=name)
    ref = np.array(lengths, dtype=float)
    first = len_curves[next(iter(models))]
    ax2.loglog(ref, first[-1] * ref[-1] / ref, "k:", lw=1, label="1 / length")
    ax2.set_xlabel("mean trace length (steps)")
    ax2.set_ylabel("demonstrations / s (median)")
    ax2.set_title(f"Throughput vs trace length ({n:,} demos)")
    ax2.legend(fontsize=8)
    ax2.grid(True, which="both", alpha=0.3)
    sec.add(save_figure(fig, cfg, "predict_throughput"))
    data["targets"] = []
    sec.data = data
    return sec
