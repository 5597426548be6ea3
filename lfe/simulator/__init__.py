"""Large-force-exercise simulator: an offensive-counter-air mission at a fixed time step.

One module per job: ``config`` (:class:`ScenarioConfig` and every constant of the model),
``_world`` (the set-up: forces, geometry, timeline, initial state), ``_tactics`` (what each
aircraft and SAM site decides at each step), ``_weapons`` (releasing and resolving weapons),
``_geometry`` (distances and angles, with :mod:`lfe.detmath`), ``_engine``
(:func:`simulate_scenario`, the time loop and the motion) and ``_output`` (the tables).
"""

from lfe.simulator._engine import simulate_scenario
from lfe.simulator.config import ScenarioConfig

__all__ = ["ScenarioConfig", "simulate_scenario"]
