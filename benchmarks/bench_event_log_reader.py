"""Event logs: XES events read per second, per-case frames, and the encoder's speed.

    python benchmarks/bench_event_log_reader.py                  # 1,000,000 events, 50,000 cases
    python benchmarks/bench_event_log_reader.py --events 200000

A synthetic XES file (each event: activity, timestamp, resource, an int) is written to a
temporary folder, then timed: ``read_event_log`` whole (the stream, ordering, labels, one
DataFrame per case), and ``EventLogEncoder`` on 50,000 cases x 20 events x 40
activities (from sequences and from the reader's DataFrames). Each time is the fastest of
``--repeats`` runs (the least disturbed by other processes). Results: RESULTS_event_logs_reader.md.
"""

import argparse
import random
import tempfile
import time
from pathlib import Path

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.io import EventLogEncoder, read_event_log


def write_xes(path, n_cases, n_events, n_activities=40, seed=0):
    """A log of ``n_cases`` traces of ``n_events`` events, a boolean label per trace."""
    rnd = random.Random(seed)
    with open(path, "w", encoding="utf-8") as f:
        f.write('<?xml version="1.0" encoding="UTF-8"?>\n'
                '<log xes.version="1.0" xmlns="http://www.xes-standard.org/">\n')
        for c in range(n_cases):
            f.write(f'<trace><string key="concept:name" value="case{c}"/>'
                    f'<boolean key="ok" value="{"true" if c % 2 else "false"}"/>\n')
            for e in range(n_events):
                a = rnd.randrange(n_activities)
                f.write(f'<event><string key="concept:name" value="act{a}"/>'
                        f'<date key="time:timestamp" value="2024-01-01T{e // 60:02d}:'
                        f'{e % 60:02d}:00.000+01:00"/><string key="org:resource" '
                        f'value="r{a % 5}"/><int key="cost" value="{e}"/></event>\n')
            f.write("</trace>\n")
        f.write("</log>\n")


def best(fn, repeats):
    """The fastest of ``repeats`` calls: (seconds, the last result)."""
    walls, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
    return min(walls), out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=1_000_000)
    parser.add_argument("--events-per-case", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    n_cases = args.events // args.events_per_case
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "log.xes"
        write_xes(path, n_cases, args.events_per_case)
        size = path.stat().st_size / 2**20
        whole, log = best(lambda: read_event_log(path, label="ok"), args.repeats)
    print(f"XES file: {args.events:,} events, {n_cases:,} cases, {size:.0f} MiB")
    print(f"  read_event_log (cases): {args.events / whole:,.0f} events/s ({whole:.2f} s)")

    # The encoder at DESIGN's largest sizes: 50,000 cases x 20 events x 40 activities.
    rnd = random.Random(1)
    seqs = [[f"act{rnd.randrange(40)}" for _ in range(20)] for _ in range(50_000)]
    enc = EventLogEncoder()
    t_seq, traces = best(lambda: enc.fit_transform(seqs), args.repeats)
    print(f"encoder, 50,000 sequences x 20 events x 40 activities: {t_seq:.2f} s "
          f"({len(traces):,} traces of {traces[0].shape})")
    if len(log.cases) >= 50_000:
        t_frames, _ = best(lambda: EventLogEncoder().fit_transform(log.cases[:50_000]),
                           args.repeats)
        print(f"encoder, the reader's 50,000 case DataFrames: {t_frames:.2f} s")
    t_check, _ = best(lambda: check_traces(traces), 1)
    print(f"BSIClassifier's validation of those 50,000 DataFrames (check_traces): "
          f"{t_check:.2f} s")


if __name__ == "__main__":
    main()
