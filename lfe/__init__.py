"""Large-force exercise (LFE) domain: simulator, commander annotations, proposition extractor."""

from lfe.annotate import (
    MISSION_OBJECTIVES,
    PHASE_NAMES,
    annotate_scenario,
    annotate_scenarios,
    phase_labels,
)
from lfe.dataset import LFEDataset, load_lfe_dataset, make_lfe_dataset, random_scenario_config
from lfe.extractor import (
    PROPOSITION_DESCRIPTIONS,
    PROPOSITION_SETS,
    LFEPropositionExtractor,
    proposition_roles,
)
from lfe.plots import plot_scenario_map, plot_timeline
from lfe.scenario import Scenario, check_scenario, check_scenarios
from lfe.simulator import ScenarioConfig, simulate_scenario

__all__ = [
    "LFEDataset",
    "LFEPropositionExtractor",
    "MISSION_OBJECTIVES",
    "PHASE_NAMES",
    "PROPOSITION_DESCRIPTIONS",
    "PROPOSITION_SETS",
    "Scenario",
    "ScenarioConfig",
    "annotate_scenario",
    "annotate_scenarios",
    "check_scenario",
    "check_scenarios",
    "load_lfe_dataset",
    "make_lfe_dataset",
    "phase_labels",
    "plot_scenario_map",
    "plot_timeline",
    "proposition_roles",
    "random_scenario_config",
    "simulate_scenario",
]
