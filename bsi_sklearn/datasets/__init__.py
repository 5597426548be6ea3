"""Generators of the paper's domains, of errand tasks and of event logs, with known rules."""

from bsi_sklearn.datasets.dinner_table import (
    dinner_table_labels,
    dinner_table_specification,
    dinner_table_tsrs,
    make_dinner_table_demos,
)
from bsi_sklearn.datasets.errands import ErrandTask, make_errand_demos, make_errand_task
from bsi_sklearn.datasets.plotting import plot_demos
from bsi_sklearn.datasets.poi_threat import (
    make_poi_threat_demos,
    poi_threat_labels,
    poi_threat_specification,
)
from bsi_sklearn.datasets.process_logs import ProcessLog, make_process_log
from bsi_sklearn.datasets.tsr import TaskSpaceRegion, make_pose

__all__ = [
    "ErrandTask",
    "ProcessLog",
    "TaskSpaceRegion",
    "dinner_table_labels",
    "dinner_table_specification",
    "dinner_table_tsrs",
    "make_dinner_table_demos",
    "make_errand_demos",
    "make_errand_task",
    "make_pose",
    "make_poi_threat_demos",
    "make_process_log",
    "plot_demos",
    "poi_threat_labels",
    "poi_threat_specification",
]
