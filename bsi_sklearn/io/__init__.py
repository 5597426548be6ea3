"""Reading and writing traces: ``.trace`` files (samples2LTL / Scarlet) and long-format CSV.

``bsi_sklearn.io.trace_file`` holds the ``.trace`` format, ``bsi_sklearn.io.long_format`` the
long format (one row per time step) of DataFrames and CSV files.
"""

from bsi_sklearn.io.long_format import (
    read_traces_csv,
    traces_from_frame,
    traces_to_frame,
    write_traces_csv,
)
from bsi_sklearn.io.trace_file import (
    TraceFile,
    load_trace_file,
    read_trace_file,
    write_trace_file,
)

__all__ = [
    "TraceFile",
    "read_trace_file",
    "load_trace_file",
    "write_trace_file",
    "read_traces_csv",
    "write_traces_csv",
    "traces_from_frame",
    "traces_to_frame",
]
