"""Generators of the paper's domains with known ground-truth specifications."""

from bsi_sklearn.datasets.dinner_table import (
    dinner_table_labels,
    dinner_table_specification,
    dinner_table_tsrs,
    make_dinner_table_demos,
)
from bsi_sklearn.datasets.plotting import plot_demos
from bsi_sklearn.datasets.poi_threat import (
    make_poi_threat_demos,
    poi_threat_labels,
    poi_threat_specification,
)
from bsi_sklearn.datasets.tsr import TaskSpaceRegion, make_pose

__all__ = [
    "TaskSpaceRegion",
    "dinner_table_labels",
    "dinner_table_specification",
    "dinner_table_tsrs",
    "make_dinner_table_demos",
    "make_pose",
    "make_poi_threat_demos",
    "plot_demos",
    "poi_threat_labels",
    "poi_threat_specification",
]
