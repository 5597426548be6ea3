"""``bsi monitor POSTERIOR FILE...``: replay demonstrations against a saved posterior.

For every demonstration of every file (``.trace`` or long-format CSV), the posterior
(:meth:`Posterior.to_json`, e.g. from ``bsi fit ... --save``) monitors it step by step; the
verdicts go to ``<stem>_<i>_monitor.csv`` and their plot, with the clause events marked, to
``<stem>_<i>_monitor.png`` in ``--out``.
"""

from pathlib import Path

import numpy as np

__all__ = ["add_arguments", "run"]


def add_arguments(parser):
    """Arguments of ``bsi monitor``."""
    parser.add_argument("posterior", metavar="POSTERIOR",
                        help="a posterior saved as JSON (bsi fit ... --save POSTERIOR)")
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help=".trace files or long-format CSV files of demonstrations")
    parser.add_argument("--out", default="bsi_monitor", metavar="DIR",
                        help="folder for the tables and plots (default: ./bsi_monitor)")
    parser.add_argument("--no-plot", action="store_true", help="write the tables only")


def _load(path):
    from bsi_sklearn import io

    if str(path).endswith(".csv"):
        return io.read_traces_csv(path)[0]
    return io.load_trace_file(path)[0]


def run(args):
    """Monitor every demonstration and write its table and plot; prints one line each."""
    from bsi_sklearn.monitor_figure import monitor_frame, plot_monitor
    from bsi_sklearn.posterior import Posterior

    posterior = Posterior.from_json(Path(args.posterior))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for path in args.files:
        for i, trace in enumerate(_load(path)):
            if not hasattr(trace, "columns"):
                trace = np.asarray(trace)
            frame = monitor_frame(posterior, trace)
            stem = out / f"{Path(path).stem}_{i}_monitor"
            frame.to_csv(stem.with_suffix(".csv"), index=False)
            if not args.no_plot:
                ax = plot_monitor(frame, title=f"{Path(path).name}, demonstration {i}")
                ax.figure.savefig(stem.with_suffix(".png"), dpi=90)
            end = frame.iloc[-1]
            first = frame.loc[frame["p_violated"] >= 0.5, "step"]
            print(f"{path} [{i}]: {len(frame) - 1} steps, P(satisfied) at the end "
                  f"{end['p_satisfied']:.3f}"
                  + (f", mostly violated from step {int(first.iloc[0])}" if len(first) else "")
                  + f" -> {stem.name}.csv")
    return 0
