"""Training time of the paper's recurrent baselines per cross-validation fold, LFE-sized data."""

import statistics
import time
import warnings

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from _common import Section, fmt_s, md_table, save_figure
from sklearn.exceptions import ConvergenceWarning
from sklearn.model_selection import KFold

from bsi_sklearn import BSIClassifier


def lfe_data(n_scenarios=None):
    """Proposition traces, flight-phase inputs, phase labels and MO1-MO3 of the LFE dataset.

    ``None`` uses the built-in dataset (24 scenarios); a number simulates that many.
    """
    import lfe

    ds = lfe.load_lfe_dataset() if n_scenarios is None else lfe.make_lfe_dataset(n_scenarios)
    ext = lfe.LFEPropositionExtractor().fit(ds.scenarios)
    traces = ext.transform(ds.scenarios)
    flight = ext.flight_phase_features(ds.scenarios)
    phases = ext.phase_labels(ds.scenarios, ds.phases)
    standalone = [t.to_numpy(dtype=np.float32) for t in traces]
    coupled = [pd.concat([t.astype(np.float32), f], axis=1).to_numpy(dtype=np.float32)
               for t, f in zip(traces, flight)]
    return {"traces": traces, "standalone": standalone, "coupled": coupled, "phases": phases,
            "y": ds.labels.to_numpy(), "objectives": list(ds.labels.columns),
            "roles": lfe.proposition_roles()}


def _fit_time(name, params, X, y, phases):
    from baselines import make_paper_baseline

    clf = make_paper_baseline(name, random_state=0, **params)
    t0 = time.perf_counter()
    clf.fit(X, y, phases=phases)
    return time.perf_counter() - t0, clf.n_epochs_


def _bsi_fold_times(data, folds, n_train):
    """Seconds per fold of one default BSIClassifier per objective (after a warm-up fit)."""
    BSIClassifier(**data["roles"], random_state=0).fit(data["traces"][:n_train],
                                                       data["y"][:n_train, 0])
    times = []
    for train, _ in folds:
        t0 = time.perf_counter()
        for k in range(data["y"].shape[1]):
            Xtr = [data["traces"][i] for i in train]
            BSIClassifier(**data["roles"], random_state=0).fit(Xtr, data["y"][train, k])
        times.append(time.perf_counter() - t0)
    return times


def run(cfg):
    from baselines import PAPER_BASELINES

    sec = Section("lstm", "LSTM baselines: training time per fold")
    data = lfe_data(cfg.pick(None, 8))
    n = len(data["y"])
    n_folds = 4
    folds = list(KFold(n_folds, shuffle=True, random_state=0).split(np.arange(n)))
    folds = folds[:cfg.pick(n_folds, 1)]
    n_train = len(folds[0][0])
    lengths = [len(t) for t in data["traces"]]
    max_epochs = cfg.pick(200, 5)
    source = cfg.pick("the built-in LFE dataset (`lfe.load_lfe_dataset()`",
                      "a small simulated LFE dataset (`lfe.make_lfe_dataset(8)`")
    sec.add(f"{source[0].upper() + source[1:]}, {n} scenarios, "
            f"{len(data['traces'][0].columns)} propositions from `LFEPropositionExtractor`, "
            f"traces of {min(lengths)} to {max(lengths)} steps), {n_folds}-fold "
            f"cross-validation: {n_train} training sequences per fold, the three objectives "
            "MO1-MO3 as one multi-output target. Coupled models also read the 40 "
            "flight-phase features and learn the scenario phase at every step. Default "
            f"`LSTMSequenceClassifier` settings (hidden 32, Adam, lr 0.01, batch 32, up to "
            f"{max_epochs} epochs, early stopping on a 20 % validation split with patience "
            "20, one torch thread), median over the {len(folds)} fold(s). *Fixed epochs* turns "
            f"early stopping off (`validation_fraction=None, patience={max_epochs}`), so the "
            f"fit runs all {max_epochs} epochs (first fold only). CPU, one torch thread.")
    rows, data_out = [], {"models": {}}
    for name in PAPER_BASELINES:
        X = data["coupled"] if PAPER_BASELINES[name]["coupled"] else data["standalone"]
        train = folds[0][0]
        # Warm-up: torch's first forward/backward of a configuration pays one-off set-up.
        _fit_time(name, {"max_epochs": 1}, [X[i] for i in train], data["y"][train],
                  [data["phases"][i] for i in train])
        res = {}
        for mode, extra in (("early stopping", {}),
                            ("fixed epochs", {"validation_fraction": None,
                                             "patience": max_epochs})):
            times, epochs = [], []
            for train, _ in folds[:len(folds) if not extra else 1]:
                t, e = _fit_time(name, {"max_epochs": max_epochs, **extra},
                                 [X[i] for i in train], data["y"][train],
                                 [data["phases"][i] for i in train])
                times.append(t)
                epochs.append(e)
            res[mode] = {"s": statistics.median(times), "epochs": statistics.median(epochs),
                         "all_s": times}
        data_out["models"][name] = res
        es, fx = res["early stopping"], res["fixed epochs"]
        rows.append([name, fmt_s(es["s"]), f"{es['epochs']:.0f}", fmt_s(fx["s"]),
                     f"{fx['epochs']:.0f}", fmt_s(fx["s"] / max(fx["epochs"], 1))])

    # BSI on the same folds: one classifier per objective, as in the paper.
    # R-hat warnings on these small, label-noisy folds are about mixing, not time: counted.
    with warnings.catch_warnings(record=True) as records:
        warnings.simplefilter("always", ConvergenceWarning)
        bsi_times = _bsi_fold_times(data, folds, n_train)
    n_warn = sum(issubclass(r.category, ConvergenceWarning) for r in records)
    bsi_s = statistics.median(bsi_times)
    data_out["bsi_three_objectives_s"] = bsi_s
    rows.append(["BSIClassifier (defaults), MO1-MO3 fitted separately", fmt_s(bsi_s), "", "",
                 "", ""])
    sec.add(md_table(["model", "train time / fold (early stopping)", "epochs",
                      f"train time / fold ({max_epochs} epochs)", "epochs", "per epoch"],
                     rows))
    sec.add("Each configuration is fitted once (1 epoch) before the timed fits, so torch's "
            "one-off set-up is not counted; the times include the per-fit work (seeding, "
            "standardisation, the validation split). The BSI row is three fits (one per "
            "objective; 5 globals x 6 subtasks, 8,296,448 hypotheses, so MCMC with 4 chains "
            "x 10,000 samples) on the DataFrame traces, validation included"
            + (f"; {n_warn} of its {3 * len(folds) + 1} fits warned that the chains disagree "
               "(split-R-hat > 1.05)." if n_warn else "."))
    fig, ax = plt.subplots(figsize=(7, 3.5))
    names = list(PAPER_BASELINES)
    x = np.arange(len(names) + 1)
    es = [data_out["models"][k]["early stopping"]["s"] for k in names] + [bsi_s]
    fx = [data_out["models"][k]["fixed epochs"]["s"] for k in names] + [np.nan]
    ax.bar(x - 0.2, es, 0.4, label="early stopping")
    ax.bar(x + 0.2, fx, 0.4, label=f"{max_epochs} epochs")
    ax.set_xticks(x, names + ["BSI (3 fits)"], fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("seconds per fold (median)")
    ax.set_title(f"Training time per fold ({n_train} LFE sequences)")
    ax.legend(fontsize=8)
    ax.grid(True, axis="y", which="both", alpha=0.3)
    sec.add(save_figure(fig, cfg, "lstm_training"))
    data_out["targets"] = []
    data_out["n_train"] = n_train
    sec.data = data_out
    return sec
