"""Output of a simulation: the recorded steps and the weapon log as a :class:`Scenario`."""

from __future__ import annotations

import numpy as np
import pandas as pd

from lfe.scenario import (
    FLIGHT_PHASES,
    SITE_COLUMNS,
    TRACK_COLUMNS,
    WEAPON_COLUMNS,
    Scenario,
    normalise_table,
)
from lfe.simulator.config import ROLE_NAMES

__all__ = ["scenario_tables"]


def scenario_tables(sim, steps, records):
    """The scenario's tables from a finished simulation.

    Parameters
    ----------
    sim : _Simulation
        The simulation, after its last step.
    steps : int
        Recorded steps.
    records : dict
        ``x``, ``y``, ``altitude``, ``speed``, ``heading``, ``phase``, ``alive``: arrays of
        shape (at least ``steps``, aircraft), one row per recorded step.

    Returns
    -------
    scenario : Scenario
    """
    c = sim.c
    n = sim.n
    time = np.repeat(np.arange(steps) * sim.dt, n)
    side = np.where(sim.friendly, "friendly", "hostile")
    role = np.array(ROLE_NAMES)[sim.role]
    phases = np.array(FLIGHT_PHASES)
    tracks = pd.DataFrame({
        "time": time,
        "aircraft_id": np.tile(np.array(sim.names), steps),
        "side": np.tile(side, steps),
        "role": np.tile(role, steps),
        "x": records["x"][:steps].ravel(),
        "y": records["y"][:steps].ravel(),
        "altitude": records["altitude"][:steps].ravel(),
        "speed": records["speed"][:steps].ravel(),
        "heading": records["heading"][:steps].ravel(),
        "flight_phase": phases[records["phase"][:steps].ravel()],
        "alive": records["alive"][:steps].ravel(),
    }, columns=list(TRACK_COLUMNS))

    def ident(who):
        kind, idx = who
        if kind == "air":
            return sim.names[idx]
        if kind in ("sam", "site"):
            return sim.sam_names[idx]
        return "target"

    rows = []
    for k, t_fired, shooter, target, weapon, impact, outcome, _ in sim.shots:
        shooter_id = ident(shooter) if isinstance(shooter, tuple) else sim.names[shooter]
        rows.append((f"w{k + 1:04d}", float(t_fired), shooter_id, ident(target), weapon,
                     float(impact), outcome))
    weapons = pd.DataFrame(rows, columns=list(WEAPON_COLUMNS))

    sites = pd.DataFrame({
        "site_id": sim.sam_names + ["target"],
        "site_type": ["sam"] * c.n_sams + ["target"],
        "x": np.append(sim.sam_xy[:, 0], sim.target[0]),
        "y": np.append(sim.sam_xy[:, 1], sim.target[1]),
        "detection_range": np.append(sim.sam_detect, 0.0),
        "weapon_range": np.append(sim.sam_range, 0.0),
    }, columns=list(SITE_COLUMNS))

    meta = {
        "scenario_id": sim.scenario_id,
        "seed": sim.seed,
        "dt": sim.dt,
        "tot_start": sim.tot_start,
        "tot_end": sim.tot_end,
        "target_id": "target",
        "n_friendly": int(c.n_friendly),
        "n_escorts": int(c.n_escorts),
        "n_sead": int(c.n_sead),
        "n_strikers": int(c.n_strikers),
        "n_hostile": int(c.n_hostile),
        "n_sams": int(c.n_sams),
        "bombs_per_striker": int(c.bombs_per_striker),
        "escort_push_planned": float(sim.escort_push),
        "striker_push_planned": float(sim.striker_push_planned),
        "config": c.to_dict(),
    }
    return Scenario(normalise_table(tracks, "tracks"), normalise_table(weapons, "weapons"),
                    normalise_table(sites, "sites"), meta)
