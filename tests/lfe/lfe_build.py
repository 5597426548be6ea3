"""Hand-built LFE scenarios for the tests: every table written out row by row, no simulator."""

import pandas as pd

from lfe import Scenario

DT = 10.0


def aircraft(side, role, *, phases=((0.0, "push"),), death=None, x0=0.0, y0=0.0, vx=1.0):
    """One aircraft: flight phases as ``(start time, phase)``, shot down at ``death`` (s)."""
    return {"side": side, "role": role, "phases": tuple(phases), "death": death,
            "x0": x0, "y0": y0, "vx": vx}


def build_tracks(fleet, t_end, dt=DT, drop_after_death=False):
    """Tracks of ``fleet`` (id -> :func:`aircraft`) every ``dt`` s from 0 to ``t_end``.

    An aircraft moves east at ``vx`` km per step while alive and stays put once shot down
    (phase ``destroyed``). ``drop_after_death`` leaves out its rows after the first dead one.
    """
    rows = []
    n_steps = int(round(t_end / dt)) + 1
    for k in range(n_steps):
        t = k * dt
        for name, a in fleet.items():
            dead = a["death"] is not None and t >= a["death"]
            if dead and drop_after_death and t - dt >= a["death"]:
                continue
            moved = min(k, int(a["death"] // dt)) if a["death"] is not None else k
            phase = [p for start, p in a["phases"] if start <= t][-1]
            rows.append({
                "time": t, "aircraft_id": name, "side": a["side"], "role": a["role"],
                "x": a["x0"] + a["vx"] * moved, "y": a["y0"], "altitude": 6000.0,
                "speed": 0.0 if dead else 250.0, "heading": 90.0,
                "flight_phase": "destroyed" if dead else phase, "alive": not dead,
            })
    return pd.DataFrame(rows)


def weapons_table(rows):
    """``rows``: (shot_id, fired, shooter, target, type, impact, outcome)."""
    return pd.DataFrame(list(rows), columns=["shot_id", "time_fired", "shooter", "target",
                                             "weapon_type", "time_impact", "outcome"])


def sites_table(n_sams=1):
    rows = [(f"sam_{k + 1}", "sam", 100.0, 10.0 * k, 60.0, 30.0) for k in range(n_sams)]
    rows.append(("target", "target", 120.0, 0.0, 0.0, 0.0))
    return pd.DataFrame(rows, columns=["site_id", "site_type", "x", "y", "detection_range",
                                       "weapon_range"])


def scenario(fleet, t_end, weapons=(), *, scenario_id="hand", tot=(40.0, 60.0), n_sams=1,
             dt=DT, drop_after_death=False, **meta):
    """A :class:`lfe.Scenario` from a fleet, a weapon log and a TOT window."""
    info = {"scenario_id": scenario_id, "dt": dt, "tot_start": tot[0], "tot_end": tot[1],
            "target_id": "target"}
    info.update(meta)
    return Scenario(build_tracks(fleet, t_end, dt, drop_after_death), weapons_table(weapons),
                    sites_table(n_sams), info)
