"""Child process of bench_event_logs: one row in a fresh interpreter, under the parent's limits.

Usage: ``python _event_log_child.py '<json spec>'``; prints one JSON line: the row of
``_event_log_rows.run_row`` plus ``peak_rss_mib`` (this process's ``ru_maxrss``: the
interpreter, the imports, the log and the fit together). The parent sets the address-space
limit (``RLIMIT_AS``) before this starts and kills it at its wall-clock timeout; a
``MemoryError`` here is reported as status ``memory``.
"""

import json
import resource
import sys

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split


def _peak_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def main(spec):
    try:
        from _event_log_rows import run_row

        row = run_row(spec)
    except MemoryError:
        row = dict(spec, status="memory")
    row["peak_rss_mib"] = _peak_mib()
    print(json.dumps(row, default=str), flush=True)


if __name__ == "__main__":
    main(json.loads(sys.argv[1]))
