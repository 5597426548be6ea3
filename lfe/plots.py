"""Pictures of a large-force exercise: the scenario map and the proposition timeline."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from lfe.annotate import PHASE_NAMES
from lfe.scenario import check_scenario

__all__ = ["plot_scenario_map", "plot_timeline"]

#: Track colour per (side, role): friendly roles in blues and greens, hostile in red.
ROLE_COLORS = {
    ("friendly", "escort"): "#1f77b4",
    ("friendly", "sead"): "#17becf",
    ("friendly", "striker"): "#2ca02c",
    ("hostile", "fighter"): "#d62728",
}
_PHASE_COLORS = dict(zip(PHASE_NAMES, ("#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e")))
_PHASE_TITLES = {"escort_push": "Escort Push", "strikers_push": "Strikers Push",
                 "tot": "TOT", "egress": "Egress"}


def _new_axes(ax, figsize):
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=figsize)
    return ax


def plot_scenario_map(scenario, ax=None):
    """Draw the map of one scenario: tracks, starting positions, SAM sites, target, kills.

    Each aircraft's track is a line coloured by side and role (friendly escorts blue, SEAD
    cyan, strikers green; hostile fighters red), its starting position a dot. SAM sites are
    triangles with their detection range (dotted ring) and weapon range (solid ring), the
    assigned target a star. Aircraft shot down and SAM sites destroyed are marked with a
    black ``x`` where it happened. Axes in km (x east, y north), equal aspect.

    Parameters
    ----------
    scenario : Scenario
        A raw scenario (validated first).
    ax : matplotlib Axes, default=None
        Where to draw; a new figure when None.

    Returns
    -------
    ax : matplotlib Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from lfe import ScenarioConfig, simulate_scenario
    >>> from lfe.plots import plot_scenario_map
    >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=0)
    >>> ax = plot_scenario_map(sc)
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('x (km, east)', 'y (km, north)')
    >>> len(ax.get_lines()) >= 22  # one track per aircraft, then the markers
    True
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Circle

    sc = check_scenario(scenario)
    created = ax is None
    ax = _new_axes(ax, (7.5, 6.0))
    tracks = sc.tracks
    order = np.argsort(tracks["time"].to_numpy(dtype=float), kind="stable")
    tracks = tracks.iloc[order]
    handles = {}

    for _, track in tracks.groupby(tracks["aircraft_id"].astype(str), sort=False):
        side, role = str(track["side"].iloc[0]), str(track["role"].iloc[0])
        color = ROLE_COLORS[(side, role)]
        x = track["x"].to_numpy(dtype=float)
        y = track["y"].to_numpy(dtype=float)
        alive = track["alive"].astype(bool).to_numpy()
        ax.plot(x, y, color=color, lw=0.9, alpha=0.8, zorder=2)
        ax.plot(x[0], y[0], "o", color=color, mec="k", mew=0.5, ms=4.5, zorder=4)
        handles.setdefault(f"{side} {role}", Line2D([], [], color=color, lw=1.5))
        if not alive.all():
            k = int(np.argmax(~alive))
            ax.plot(x[k], y[k], "x", color="k", ms=7, mew=1.8, zorder=6)
            handles.setdefault("shot down / destroyed",
                               Line2D([], [], ls="", marker="x", color="k", ms=7, mew=1.8))
    handles["start"] = Line2D([], [], ls="", marker="o", color="0.6", mec="k", mew=0.5, ms=4.5)

    sites = sc.sites
    weapons = sc.weapons
    site_hit = set(weapons.loc[weapons["outcome"].astype(str) == "hit", "target"].astype(str))
    target_id = str(sc.meta["target_id"])
    for _, site in sites.iterrows():
        sx, sy = float(site["x"]), float(site["y"])
        sid = str(site["site_id"])
        if str(site["site_type"]) == "sam":
            ax.plot(sx, sy, "^", color="#8c2d04", mec="k", mew=0.5, ms=9, zorder=5)
            for radius, ls, key in ((float(site["detection_range"]), ":", "SAM detection range"),
                                    (float(site["weapon_range"]), "-", "SAM weapon range")):
                if radius > 0:
                    ax.add_patch(Circle((sx, sy), radius, fill=False, ec="#8c2d04", ls=ls,
                                        lw=1.0, alpha=0.8, zorder=1))
                    handles.setdefault(key, Line2D([], [], color="#8c2d04", ls=ls, lw=1.0))
            handles.setdefault("SAM site", Line2D([], [], ls="", marker="^", color="#8c2d04",
                                                  mec="k", mew=0.5, ms=9))
            if sid in site_hit:
                ax.plot(sx, sy, "x", color="k", ms=7, mew=1.8, zorder=6)
        else:
            hit = sid == target_id and sid in site_hit
            ax.plot(sx, sy, "*", color="gold", mec="k", mew=0.8, ms=16, zorder=5)
            label = "target (hit)" if hit else "target"
            handles.setdefault(label, Line2D([], [], ls="", marker="*", color="gold", mec="k",
                                             mew=0.8, ms=14))

    ax.set_xlabel("x (km, east)")
    ax.set_ylabel("y (km, north)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.set_title(f"Scenario {sc.scenario_id}: TOT {float(sc.meta['tot_start']):g}"
                 f"-{float(sc.meta['tot_end']):g} s")
    # legend: tracks by side and role first, then the markers
    first = [f"{side} {role}" for side, role in ROLE_COLORS]
    keys = [k for k in first if k in handles] + [k for k in handles if k not in first]
    ax.legend([handles[k] for k in keys], keys, loc="upper left", fontsize=7,
              framealpha=0.85)
    if created:
        ax.figure.tight_layout()
    return ax


def _check_trace(trace):
    if not isinstance(trace, pd.DataFrame):
        raise ValueError(
            f"trace must be a DataFrame of propositions (LFEPropositionExtractor.transform), "
            f"got {type(trace).__name__}"
        )
    if trace.shape[0] == 0 or trace.shape[1] == 0:
        raise ValueError(f"trace is empty (shape {trace.shape})")
    times = pd.to_numeric(pd.Series(trace.index), errors="coerce").to_numpy(dtype=float)
    if not np.all(np.isfinite(times)) or np.any(np.diff(times) <= 0):
        raise ValueError("trace index must be increasing times (s)")
    values = {}
    for col in trace.columns:
        v = trace[col]
        if v.dtype == bool:
            values[str(col)] = v.to_numpy()
            continue
        arr = pd.to_numeric(v, errors="coerce").to_numpy(dtype=float)
        if not np.all(np.isin(arr, (0.0, 1.0))):
            raise ValueError(f"trace column {col!r} is not boolean (or 0/1)")
        values[str(col)] = arr.astype(bool)
    return times, values


def _check_phases(phases):
    if isinstance(phases, pd.DataFrame):
        if len(phases) != 1:
            raise ValueError(
                f"phases must be one scenario's row (a Series or mapping), got a DataFrame "
                f"with {len(phases)} rows"
            )
        phases = phases.iloc[0]
    if not isinstance(phases, (Mapping, pd.Series)):
        raise ValueError(
            f"phases must be a Series or mapping with keys {list(PHASE_NAMES)}, got "
            f"{type(phases).__name__}"
        )
    out = {}
    for name in PHASE_NAMES:
        if name not in phases:
            raise ValueError(f"phases is missing key {name!r}")
        try:
            value = float(phases[name])
        except (TypeError, ValueError):
            value = np.nan
        if not np.isfinite(value):
            raise ValueError(f"phases[{name!r}] must be a finite time (s), got "
                             f"{phases[name]!r}")
        out[name] = value
    return out


def plot_timeline(trace, phases=None, ax=None):
    """Draw one scenario's propositions over time, with the commander's phase transitions.

    One row per proposition (top to bottom in column order), a bar wherever it holds; each
    bar covers a time step from its row's time to the next one. The four phase transition
    times (Escort Push, Strikers Push, TOT, Egress) are vertical lines, named in the legend
    and above the axes.

    Parameters
    ----------
    trace : DataFrame
        Boolean propositions of one scenario, index time (s): an element of
        :meth:`LFEPropositionExtractor.transform`'s output.
    phases : Series or mapping, default=None
        The scenario's transition times, keys :data:`lfe.PHASE_NAMES` (a row of
        ``LFEDataset.phases``). None draws no lines.
    ax : matplotlib Axes, default=None
        Where to draw; a new figure when None.

    Returns
    -------
    ax : matplotlib Axes

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from lfe import (LFEPropositionExtractor, ScenarioConfig, annotate_scenarios,
    ...                  simulate_scenario)
    >>> from lfe.plots import plot_timeline
    >>> sc = simulate_scenario(ScenarioConfig(n_hostile=4, n_sams=1), random_state=0)
    >>> trace = LFEPropositionExtractor().fit_transform([sc])[0]
    >>> _, phases = annotate_scenarios([sc])
    >>> ax = plot_timeline(trace, phases.iloc[0])
    >>> [t.get_text() for t in ax.get_yticklabels()][:2]
    ['hostile_attrition_50', 'hostile_attrition_75']
    >>> ax.get_legend().get_texts()[2].get_text()[:3]
    'TOT'
    """
    times, values = _check_trace(trace)
    marks = None if phases is None else _check_phases(phases)
    names = list(values)
    created = ax is None
    ax = _new_axes(ax, (10.0, 0.32 * len(names) + 1.6))
    step = float(np.median(np.diff(times))) if len(times) > 1 else 1.0
    widths = np.append(np.diff(times), step)
    for row, name in enumerate(names):
        on = values[name]
        if not on.any():
            continue
        # runs of consecutive true steps become one bar each
        edges = np.diff(np.concatenate(([0], on.astype(np.int8), [0])))
        starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
        spans = [(times[a], times[b - 1] + widths[b - 1] - times[a])
                 for a, b in zip(starts, stops)]
        ax.broken_barh(spans, (row - 0.35, 0.7), facecolors="#4c72b0", edgecolor="none")
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels(names, fontsize=8)
    ax.set_ylim(len(names) - 0.5, -0.5)
    ax.set_xlim(times[0], times[-1] + widths[-1])
    ax.set_xlabel("time (s)")
    ax.grid(True, axis="x", alpha=0.3)
    if marks is not None:
        for name, t in marks.items():
            ax.axvline(t, color=_PHASE_COLORS[name], lw=1.6, ls="--",
                       label=f"{_PHASE_TITLES[name]} ({t:g} s)")
        top = ax.secondary_xaxis("top")
        top.set_xticks(list(marks.values()),
                       labels=[_PHASE_TITLES[n] for n in marks], fontsize=7, rotation=30)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, framealpha=0.85)
    if created:
        ax.figure.tight_layout()
    return ax
