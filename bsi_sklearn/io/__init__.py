"""Reading and writing traces: `.trace` files (samples2LTL / Scarlet), long-format CSV, event logs.

``bsi_sklearn.io.trace_file`` holds the ``.trace`` format, ``bsi_sklearn.io.long_format`` the
long format (one row per time step) of DataFrames and CSV files, ``bsi_sklearn.io.event_log``
the event logs (XES, CSV, event DataFrames) and ``bsi_sklearn.io.event_log_encoder`` their
encoding as traces; :func:`write_atomic` and
:func:`write_files_atomic` write files in one step (all or none). The names are imported on
first use, so that the light parts (``bsi_sklearn.io._atomic``, the posterior file's
constants) load without pandas.
"""

from bsi_sklearn._lazy import lazy_names

__all__ = [
    "TraceFile",
    "read_trace_file",
    "load_trace_file",
    "write_trace_file",
    "read_traces_csv",
    "write_traces_csv",
    "traces_from_frame",
    "traces_to_frame",
    "write_atomic",
    "write_files_atomic",
    "EventLog",
    "read_event_log",
    "EventLogEncoder",
]

_MODULES = {
    "TraceFile": "bsi_sklearn.io.trace_file",
    "read_trace_file": "bsi_sklearn.io.trace_file",
    "load_trace_file": "bsi_sklearn.io.trace_file",
    "write_trace_file": "bsi_sklearn.io.trace_file",
    "read_traces_csv": "bsi_sklearn.io.long_format",
    "write_traces_csv": "bsi_sklearn.io.long_format",
    "traces_from_frame": "bsi_sklearn.io.long_format",
    "traces_to_frame": "bsi_sklearn.io.long_format",
    "write_atomic": "bsi_sklearn.io._atomic",
    "write_files_atomic": "bsi_sklearn.io._atomic",
    "EventLog": "bsi_sklearn.io.event_log",
    "read_event_log": "bsi_sklearn.io.event_log",
    "EventLogEncoder": "bsi_sklearn.io.event_log_encoder",
}


__getattr__, __dir__ = lazy_names("bsi_sklearn.io", _MODULES, globals())
