"""The scenario map and the proposition timeline: figures drawn and saved as PNG."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402
from lfe_build import aircraft, scenario  # noqa: E402

from lfe import LFEPropositionExtractor, annotate_scenarios  # noqa: E402
from lfe.plots import plot_scenario_map, plot_timeline  # noqa: E402

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def simulated(default_dataset):
    """The first default scenario with SAM sites, its trace and its phase times."""
    k = next(i for i, sc in enumerate(default_dataset.scenarios) if sc.meta["n_sams"] > 0)
    sc = default_dataset.scenarios[k]
    trace = LFEPropositionExtractor(propositions="extended").fit_transform([sc])[0]
    return sc, trace, default_dataset.phases.iloc[k]


def _saved(ax, path):
    ax.figure.savefig(path, dpi=80)
    data = path.read_bytes()
    assert data.startswith(PNG)
    return len(data)


def test_scenario_map(simulated, tmp_path):
    sc, _, _ = simulated
    ax = plot_scenario_map(sc)
    n_aircraft = sc.tracks["aircraft_id"].nunique()
    n_dead = sc.tracks.loc[~sc.tracks["alive"], "aircraft_id"].nunique()
    lines = ax.get_lines()
    # a track and a start marker per aircraft, a cross per loss, a marker per site
    assert len(lines) >= 2 * n_aircraft + n_dead + len(sc.sites)
    # two range rings per SAM site
    assert len(ax.patches) == 2 * sc.meta["n_sams"]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels[:4] == ["friendly escort", "friendly sead", "friendly striker",
                          "hostile fighter"]
    assert {"start", "SAM site", "SAM weapon range", "SAM detection range"} <= set(labels)
    assert any(label.startswith("target") for label in labels)
    assert ax.get_xlabel() == "x (km, east)" and ax.get_aspect() == 1.0
    assert _saved(ax, tmp_path / "map.png") > 20_000


def test_scenario_map_on_given_axes_and_hand_built_scenario(tmp_path):
    fleet = {"escort_01": aircraft("friendly", "escort"),
             "striker_01": aircraft("friendly", "striker", y0=5.0),
             "fighter_01": aircraft("hostile", "fighter", death=30.0, x0=60.0, vx=-1.0)}
    shots = [("w1", 20.0, "escort_01", "fighter_01", "aam", 30.0, "hit"),
             ("w2", 30.0, "escort_01", "sam_1", "harm", 40.0, "hit")]
    sc = scenario(fleet, 60.0, shots)
    fig, (left, right) = plt.subplots(1, 2)
    assert plot_scenario_map(sc, ax=right) is right
    assert not left.get_lines()
    labels = [t.get_text() for t in right.get_legend().get_texts()]
    assert "friendly sead" not in labels and "shot down / destroyed" in labels
    # the fighter's cross sits where it was shot down; the SAM site's on the site
    crosses = [ln for ln in right.get_lines() if ln.get_marker() == "x"]
    assert sorted((float(c.get_xdata()[0]), float(c.get_ydata()[0])) for c in crosses) == [
        (57.0, 0.0), (100.0, 0.0)]
    assert _saved(right, tmp_path / "hand.png") > 5_000


def test_timeline(simulated, tmp_path):
    sc, trace, phases = simulated
    ax = plot_timeline(trace, phases)
    ticks = [t.get_text() for t in ax.get_yticklabels()]
    assert ticks == list(trace.columns)
    # one bar collection per proposition that holds at some time
    assert len(ax.collections) == int(trace.any().sum())
    vertical = [ln for ln in ax.get_lines() if len(set(ln.get_xdata())) == 1]
    assert sorted(float(ln.get_xdata()[0]) for ln in vertical) == sorted(phases.tolist())
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert [s.split(" (")[0] for s in legend] == ["Escort Push", "Strikers Push", "TOT",
                                                  "Egress"]
    assert _saved(ax, tmp_path / "timeline.png") > 15_000


def test_timeline_bars_cover_the_true_steps():
    trace = pd.DataFrame({"a": [True, True, False, True], "b": [False] * 4},
                         index=pd.Index([0.0, 10.0, 20.0, 30.0], name="time"))
    ax = plot_timeline(trace)
    (bars,) = ax.collections
    # one bar per run of true steps, each step lasting until the next (the last one 10 s)
    xs = sorted((float(v[:, 0].min()), float(v[:, 0].max()))
                for v in (path.vertices for path in bars.get_paths()))
    assert xs == [(0.0, 20.0), (30.0, 40.0)]
    assert ax.get_legend() is None  # no phases, no lines
    # 0/1 integers are accepted as well
    plot_timeline(trace.astype(int), {"escort_push": 0, "strikers_push": 5, "tot": 10,
                                      "egress": 20})


@pytest.mark.parametrize("trace, phases, match", [
    ([[True]], None, "trace must be a DataFrame"),
    (pd.DataFrame({"a": [0.5, 1.0]}), None, "trace column 'a' is not boolean"),
    (pd.DataFrame({"a": [True, False]}, index=[10.0, 0.0]), None,
     "trace index must be increasing times"),
    (pd.DataFrame({"a": []}, dtype=bool), None, "trace is empty"),
    (pd.DataFrame({"a": [True]}), {"escort_push": 0, "tot": 1, "egress": 2},
     "phases is missing key 'strikers_push'"),
    (pd.DataFrame({"a": [True]}), [1, 2, 3, 4], "phases must be a Series or mapping"),
    (pd.DataFrame({"a": [True]}), {"escort_push": 0, "strikers_push": "late", "tot": 1,
                                   "egress": 2}, r"phases\['strikers_push'\] must be a finite"),
])
def test_timeline_bad_input(trace, phases, match):
    with pytest.raises(ValueError, match=match):
        plot_timeline(trace, phases)


def test_timeline_accepts_a_one_row_phases_frame():
    fleet = {"escort_01": aircraft("friendly", "escort"),
             "striker_01": aircraft("friendly", "striker")}
    sc = scenario(fleet, 50.0)
    _, phases = annotate_scenarios([sc])
    trace = LFEPropositionExtractor().fit_transform([sc])[0]
    ax = plot_timeline(trace, phases)
    assert len(ax.get_legend().get_texts()) == 4
    with pytest.raises(ValueError, match="one scenario's row"):
        plot_timeline(trace, pd.concat([phases, phases]))


def test_map_rejects_bad_scenarios():
    with pytest.raises(ValueError, match="expected a Scenario"):
        plot_scenario_map("lfe-000")


def test_map_of_a_quiet_scenario():
    """No weapons, no SAM sites, nobody lost: tracks, starts and the target only."""
    fleet = {"escort_01": aircraft("friendly", "escort"),
             "striker_01": aircraft("friendly", "striker", y0=3.0)}
    ax = plot_scenario_map(scenario(fleet, 30.0, [], n_sams=0))
    assert [t.get_text() for t in ax.get_legend().get_texts()] == [
        "friendly escort", "friendly striker", "start", "target"]
    assert not ax.patches
