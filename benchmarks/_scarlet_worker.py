"""Scarlet in a worker process: one JSON request a line on stdin, one JSON reply on stdout.

Started by :class:`external_scarlet.ScarletWorker` as ``python -u _scarlet_worker.py`` with
Scarlet's private install directory first on ``PYTHONPATH``. It prints ``{"ready": true}``
once Scarlet is imported, then for each request ``{"trace", "csv", "thres"}`` one reply:
``{"formula": <repr or null>, "seconds"}``, or ``{"error", "seconds"}`` when Scarlet raised
(the worker goes on with the next request).
"""

import json
import logging
import sys
import time
from pathlib import Path

OPERATORS = ["F", "G", "X", "&", "|", "!"]


def _die_with_parent():
    """Be killed with the benchmark process (Linux), not after a long inference."""
    try:
        import ctypes
        import signal

        ctypes.CDLL("libc.so.6").prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except Exception:
        pass


def main():
    """Serve requests until stdin closes."""
    _die_with_parent()
    # the benchmarks' own folder (this file's) must not shadow a module Scarlet imports
    here = Path(__file__).resolve().parent
    sys.path[:] = [p for p in sys.path if not p or Path(p).resolve() != here]
    logging.disable(logging.CRITICAL)
    from Scarlet.inferLTL import inferLTL
    from Scarlet.sample import Sample

    print(json.dumps({"ready": True}), flush=True)
    for line in sys.stdin:
        req = json.loads(line)
        sample = Sample(positive=[], negative=[])
        sample.readFromFile(req["trace"])
        t0 = time.perf_counter()
        try:
            f = inferLTL(sample, req["csv"], OPERATORS, "SC", 0, False, False, req["thres"], {})
            out = {"formula": None if f is None else repr(f)}
        except Exception as exc:  # reported per file, the worker goes on
            out = {"error": type(exc).__name__ + ": " + str(exc)[:200]}
        out["seconds"] = time.perf_counter() - t0
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
