"""Monitoring a growing trace under a posterior (DESIGN §10): three-valued verdicts, step by step.

``posterior_monitor`` holds :class:`PosteriorMonitor` (every clause open, satisfied or
violated after each step; the posterior mass of the specifications satisfied, violated and
still open), :class:`Verdict`, :class:`ClauseEvent` and :func:`monitor_traces`; ``figure`` the
verdicts as a frame and a plot (:func:`monitor_frame`, :func:`plot_monitor`). The names are
imported on first use (the figure's matplotlib only with it).
"""

from bsi_sklearn._lazy import lazy_names

__all__ = ["ClauseEvent", "PosteriorMonitor", "Verdict", "monitor_traces", "monitor_frame",
           "plot_monitor"]

_MODULES = {**dict.fromkeys(["ClauseEvent", "PosteriorMonitor", "Verdict", "monitor_traces"],
                            "bsi_sklearn.monitor.posterior_monitor"),
            **dict.fromkeys(["monitor_frame", "plot_monitor"], "bsi_sklearn.monitor.figure")}

__getattr__, __dir__ = lazy_names("bsi_sklearn.monitor", _MODULES, globals())
