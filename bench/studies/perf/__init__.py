"""Speed benchmarks (``stripebench perf``). Targets live here, never in unit tests."""
