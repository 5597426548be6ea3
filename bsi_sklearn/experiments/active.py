"""``bsi reproduce active``: entropy sampling against random queries on the synthetic domain.

Per seed, the POI / threat simulator draws a pool of acceptable and unacceptable
demonstrations of one scenario. Learning starts from one labelled acceptable demonstration;
after each fit, a strategy picks the next demonstration of the pool to label: the one with
the highest vote entropy (:func:`bsi_sklearn.active.entropy_sampling`) or one drawn at random.
Both strategies start from the same demonstration and query the same pool, so the comparison
is paired. After every label we record whether the MAP specification equals the ground truth,
the posterior's entropy and its expected similarity to the ground truth.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.utils import Bunch, check_random_state

from bsi_sklearn.active import entropy_sampling
from bsi_sklearn.classifier import BSIClassifier
from bsi_sklearn.datasets import make_poi_threat_demos
from bsi_sklearn.experiments._claims import Claim, claims_frame
from bsi_sklearn.experiments._plots import new_figure, save_figure
from bsi_sklearn.experiments.tables import markdown_table
from bsi_sklearn.io import write_files_atomic
from bsi_sklearn.metrics import expected_similarity

__all__ = ["STRATEGIES", "active_learning_curve", "run_active"]

STRATEGIES = ("entropy", "random")
#: Full run: seeds, pool (acceptable, unacceptable), labels queried after the first one.
FULL = {"n_seeds": 20, "n_pool": (15, 15), "n_queries": 15, "scenarios": (1, 2, 3)}
QUICK = {"n_seeds": 2, "n_pool": (3, 3), "n_queries": 2, "scenarios": (1,)}


def active_learning_curve(data, strategy, *, first, n_queries, random_state=None,
                          classifier_params=None):
    """Label the pool one demonstration at a time and record the posterior after each label.

    Parameters
    ----------
    data : Bunch
        From :func:`~bsi_sklearn.datasets.make_poi_threat_demos` (``traces``, ``labels``,
        ``roles``, ``specification``).
    strategy : {"entropy", "random"}
    first : int
        Index of the demonstration labelled at the start.
    n_queries : int
        Labels to ask for (at most the rest of the pool).
    random_state : int or None
        Draws of the random strategy.
    classifier_params : dict, default=None
        Extra :class:`BSIClassifier` parameters (``likelihood="cb"``, the paper's, unless
        given).

    Returns
    -------
    curve : DataFrame
        One row per fit: ``n_labels``, ``map_correct``, ``entropy`` (nats),
        ``expected_similarity``, ``queried`` (index of the next demonstration asked for, -1
        after the last fit) and its ``label``.
    """
    if strategy not in STRATEGIES:
        raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
    rng = check_random_state(random_state)
    truth = data.specification
    labelled, pool = [first], [i for i in range(len(data.traces)) if i != first]
    rows = []
    for step in range(min(n_queries, len(pool)) + 1):
        # the paper's likelihood (CB) unless classifier_params says otherwise
        params = {"likelihood": "cb", **(classifier_params or {})}
        clf = BSIClassifier(**data.roles, random_state=0, **params)
        clf.fit([data.traces[i] for i in labelled], data.labels[labelled])
        nxt = -1
        if step < min(n_queries, len(pool)):
            if strategy == "entropy":
                k = int(entropy_sampling(clf, [data.traces[i] for i in pool])[0])
            else:
                k = int(rng.randint(len(pool)))
            nxt = pool.pop(k)
        rows.append({"n_labels": len(labelled),
                     "map_correct": bool(clf.map_specification_ == truth),
                     "entropy": clf.posterior_.entropy(),
                     "expected_similarity": expected_similarity(clf.posterior_, truth),
                     "queried": nxt, "label": int(data.labels[nxt]) if nxt >= 0 else -1})
        if nxt >= 0:
            labelled.append(nxt)
    return pd.DataFrame(rows)


def _interval(values):
    """Mean and the half-width of its 95% t interval."""
    from scipy import stats

    v = np.asarray(values, dtype=float)
    v = v[~np.isnan(v)]
    if len(v) == 0:
        return float("nan"), float("nan")
    if len(v) == 1:
        return float(v[0]), float("nan")
    return float(v.mean()), float(stats.t.ppf(0.975, len(v) - 1) * v.std(ddof=1)
                                  / np.sqrt(len(v)))


def _labels_to_truth(curve):
    """Labels after which the MAP equals the ground truth and stays so.

    A run that never gets there counts as one label more than it was given (a lower bound).
    """
    ok = curve["map_correct"].to_numpy()
    if not ok[-1]:
        return float(curve["n_labels"].iloc[-1] + 1)
    last_wrong = np.flatnonzero(~ok)
    k = 0 if len(last_wrong) == 0 else last_wrong[-1] + 1
    return float(curve["n_labels"].iloc[k])


def run_active(out=None, *, quick=False, scenarios=None, n_seeds=None, n_queries=None,
               random_state=0, verbose=0):
    """Run the experiment; write the table, the figure and the raw curves into ``out``.

    Parameters
    ----------
    out : str or path-like, default=None
        Output folder (nothing written when None).
    quick : bool, default=False
        Scenario 1 only, two seeds, a pool of 3 + 3, two queries: seconds, for the tests.
    scenarios : sequence of {1, 2, 3}, default=None
        The paper's scenarios; all three by default (Scenario 1 with ``quick``).
    n_seeds : int, default=None
        Seeds (pools); 20 by default.
    n_queries : int, default=None
        Labels asked for after the first; 15 by default.
    random_state : int, default=0
    verbose : int, default=0

    Returns
    -------
    result : Bunch
        ``curves`` (one row per seed, strategy and fit), ``summary`` (mean and interval per
        strategy and label count), ``labels_needed`` (per seed and strategy), ``claims``,
        ``files``, ``config``, ``elapsed``.
    """
    t0 = time.perf_counter()
    cfg = dict(QUICK if quick else FULL)
    cfg["n_seeds"] = n_seeds or cfg["n_seeds"]
    cfg["n_queries"] = n_queries or cfg["n_queries"]
    cfg["scenarios"] = tuple(scenarios or cfg["scenarios"])
    rng = check_random_state(random_state)
    seeds = rng.randint(np.iinfo(np.int32).max, size=cfg["n_seeds"])
    curves, needed = [], []
    for scenario in cfg["scenarios"]:
        for s, seed in enumerate(seeds):
            data = make_poi_threat_demos(scenario, n_demos=cfg["n_pool"][0],
                                         n_negative=cfg["n_pool"][1], random_state=int(seed))
            first = int(np.random.RandomState(seed).randint(cfg["n_pool"][0]))  # a positive
            for strategy in STRATEGIES:
                curve = active_learning_curve(data, strategy, first=first,
                                              n_queries=cfg["n_queries"],
                                              random_state=int(seed))
                curves.append(curve.assign(scenario=scenario, seed=s, strategy=strategy))
                needed.append({"scenario": scenario, "seed": s, "strategy": strategy,
                               "labels_to_truth": _labels_to_truth(curve),
                               "reached": bool(curve["map_correct"].iloc[-1])})
            if verbose:
                print(f"scenario {scenario}, seed {s + 1}/{len(seeds)} done "
                      f"({time.perf_counter() - t0:.0f} s)")
    curves = pd.concat(curves, ignore_index=True)
    needed = pd.DataFrame(needed)
    summary = _summary(curves)
    claims = _claims(needed, summary, cfg)
    result = Bunch(curves=curves, summary=summary, labels_needed=needed,
                   claims=claims_frame(claims), files=[], elapsed=0.0,
                   config={**cfg, "random_state": random_state,
                           "n_fits": len(curves)})
    result.elapsed = time.perf_counter() - t0
    result.config["seconds"] = round(result.elapsed, 1)
    if out is not None:
        result.files = _write(Path(out), result)
    return result


def _summary(curves):
    rows = []
    for (scenario, strategy, n), grp in curves.groupby(["scenario", "strategy", "n_labels"]):
        row = {"scenario": int(scenario), "strategy": strategy, "n_labels": int(n),
               "n_seeds": len(grp)}
        for metric in ("map_correct", "entropy", "expected_similarity"):
            row[f"{metric}_mean"], row[f"{metric}_ci95"] = _interval(grp[metric])
        rows.append(row)
    return pd.DataFrame(rows)


def _claims(needed, summary, cfg):
    claims = []
    for scenario in cfg["scenarios"]:
        nd = needed[needed["scenario"] == scenario]
        sm = summary[summary["scenario"] == scenario]
        text, mean = {}, {}
        for strategy in STRATEGIES:
            v = nd[nd["strategy"] == strategy]
            mean[strategy], ci = _interval(v["labels_to_truth"])
            text[strategy] = (f"{strategy} {mean[strategy]:.1f} ± {ci:.1f} "
                              f"({int(v['reached'].sum())}/{len(v)} seeds reached it)")
        last = sm["n_labels"].max()
        sim = {s: float(sm.loc[(sm["strategy"] == s) & (sm["n_labels"] == last),
                               "expected_similarity_mean"].iloc[0]) for s in STRATEGIES}
        experiment = f"active learning, scenario {scenario} ({cfg['n_seeds']} seeds)"
        claims += [
            Claim(f"AL{scenario}-labels", experiment, "entropy sampling needs fewer labels "
                  "than random queries until the MAP is the ground truth",
                  "mean labels (entropy) < mean labels (random); a seed that never gets there "
                  "counts as the budget + 1", "; ".join(text.values()), mean["entropy"],
                  bool(mean["entropy"] < mean["random"])),
            Claim(f"AL{scenario}-similarity", experiment, "after the last label, the "
                  "entropy-sampled posterior is at least as close to the ground truth",
                  "expected similarity (entropy) >= expected similarity (random)",
                  f"entropy {sim['entropy']:.3f}; random {sim['random']:.3f} at {last} labels",
                  sim["entropy"], sim["entropy"] >= sim["random"]),
        ]
    return claims


def _figure(summary):
    scenarios = sorted(summary["scenario"].unique())
    fig, axes = new_figure(3, len(scenarios), width=4.0, height=3.0)
    panels = (("map_correct", "fraction of seeds with MAP = truth"),
              ("entropy", "posterior entropy (nats)"),
              ("expected_similarity", "expected similarity to truth"))
    for row, scenario in zip(axes, scenarios):
        for ax, (metric, ylabel) in zip(row, panels):
            _panel(ax, summary[summary["scenario"] == scenario], metric)
            ax.set_title(f"scenario {scenario}", fontsize=9)
            ax.set_ylabel(ylabel)
    fig.suptitle("Entropy sampling vs random queries (mean, 95% interval over seeds)",
                 fontsize=10)
    return fig


def _panel(ax, summary, metric):
    for strategy, color in zip(STRATEGIES, ("tab:blue", "tab:orange")):
        s = summary[summary["strategy"] == strategy]
        mean, ci = s[f"{metric}_mean"].to_numpy(), s[f"{metric}_ci95"].to_numpy()
        ax.plot(s["n_labels"], mean, "o-", color=color, label=strategy, markersize=3)
        ax.fill_between(s["n_labels"], mean - np.nan_to_num(ci), mean + np.nan_to_num(ci),
                        color=color, alpha=0.2)
    ax.set_xlabel("labelled demonstrations")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def _write(out, result):
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "active_curves.csv", out / "active_summary.csv", out / "active_claims.csv",
             out / "active_config.json", out / "active_report.md", out / "active_curves.png"]
    contents = {files[0]: result.curves.to_csv(index=False),
                files[1]: result.summary.to_csv(index=False),
                files[2]: result.claims.to_csv(index=False),
                files[3]: json.dumps(result.config, indent=1) + "\n"}
    needed = result.labels_needed.pivot(index=["scenario", "seed"], columns="strategy",
                                        values="labels_to_truth").reset_index()
    table = result.summary[["scenario", "strategy", "n_labels", "map_correct_mean", "entropy_mean",
                            "entropy_ci95", "expected_similarity_mean",
                            "expected_similarity_ci95"]]
    contents[files[4]] = "\n\n".join([
        "# Active learning: entropy sampling vs random queries",
        __doc__.split("\n\n", 1)[1].strip(),
        f"Configuration: `{json.dumps(result.config)}`.",
        "## Claims", markdown_table(result.claims[["id", "criterion", "measured", "status"]]),
        "## Labels until the MAP is the ground truth (and stays so), per seed",
        "A seed that never gets there within the budget counts as the budget + 1.",
        markdown_table(needed, floatfmt=".0f"),
        "## Posterior after each label (mean and 95% half-interval over seeds)",
        markdown_table(table, floatfmt=".3f"),
        "![curves](active_curves.png)",
    ]) + "\n"
    write_files_atomic(contents)  # all or nothing
    save_figure(_figure(result.summary), files[5])
    return files
