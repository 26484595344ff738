"""The harness: evaluation, files of a run, configuration, running, reports, studies, the CLI.

One sub-package per layer, lowest first. A module imports only from its own
layer or a lower one (module-level and function-level imports alike), and the
modules of one layer import each other without cycles; ``tests/test_layout.py``
enforces both, so a new sub-package must be added to :data:`LAYERS`:

0. ``errors`` (one module, imports nothing): :class:`bench.errors.StripebenchError`, the base of every
   expected failure (one line for the user), and its configuration and input subclasses
1. ``evaluate`` (pure: arrays and tables in, numbers out): triangulation, restoration, metrics (the one
   hit rule), statistics, per-run tables, sweep curves, sim-to-real numbers
2. ``store``: every file a run writes or reads (atomic writes, run folders, checkpoints, figure data,
   summaries, baselines, the real-set layout and image readers), each format versioned
3. ``config``: the configuration schema, its defaults and comments, the embedded profiles
4. ``run``: scans, experiments, render-ahead, real-photograph runs, sweeps, the regression gate
5. ``report``: figures and HTML pages built from saved runs only
6. ``studies``: sub-pixel estimators, translucency, tuning procedures, speed benchmarks (``perf``)
7. ``api``: the notebook API (``bench.api.evaluate`` one tracker on a profile, ``bench.api.load_run``)
8. ``cli``: the ``stripebench`` command tree

``bench`` uses ``trackers`` (pixels only) and ``scenes`` (rendering); neither
of them imports ``bench``.
"""

LAYERS = ("errors", "evaluate", "store", "config", "run", "report", "studies", "api", "cli")
