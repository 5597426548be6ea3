"""Large-force exercise (LFE) domain: simulator, commander annotations, proposition extractor.

Names are imported on first use (the command line's ``--help`` stays fast).
"""

import importlib

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

_MODULES = {
    "LFEDataset": "lfe.dataset",
    "LFEPropositionExtractor": "lfe.extractor",
    "MISSION_OBJECTIVES": "lfe.annotate",
    "PHASE_NAMES": "lfe.annotate",
    "PROPOSITION_DESCRIPTIONS": "lfe.propositions",
    "PROPOSITION_SETS": "lfe.propositions",
    "Scenario": "lfe.scenario",
    "ScenarioConfig": "lfe.simulator",
    "annotate_scenario": "lfe.annotate",
    "annotate_scenarios": "lfe.annotate",
    "check_scenario": "lfe.scenario",
    "check_scenarios": "lfe.scenario",
    "load_lfe_dataset": "lfe.dataset",
    "make_lfe_dataset": "lfe.dataset",
    "phase_labels": "lfe.annotate",
    "plot_scenario_map": "lfe.plots",
    "plot_timeline": "lfe.plots",
    "proposition_roles": "lfe.propositions",
    "random_scenario_config": "lfe.dataset",
    "simulate_scenario": "lfe.simulator",
}


def __getattr__(name):
    if name in _MODULES:
        value = getattr(importlib.import_module(_MODULES[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'lfe' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_MODULES))
