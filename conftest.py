"""Root pytest configuration: keep doctest collection away from command-line entry points."""

collect_ignore_glob = ["*/__main__.py", "notebooks/*", "benchmarks/*"]
