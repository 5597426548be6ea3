"""Generators of the paper's domains with known ground-truth specifications."""

from bsi_sklearn.datasets.poi_threat import (
    make_poi_threat_demos,
    plot_demos,
    poi_threat_labels,
    poi_threat_specification,
)
from bsi_sklearn.datasets.tsr import TaskSpaceRegion, make_pose

__all__ = [
    "TaskSpaceRegion",
    "make_pose",
    "make_poi_threat_demos",
    "plot_demos",
    "poi_threat_labels",
    "poi_threat_specification",
]
