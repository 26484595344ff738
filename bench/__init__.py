"""The harness: scans, metrics, statistics, run folders, reports, the regression gate, the CLI.

Layers, lowest first; a module imports only from its own layer or a lower one
(module-level and function-level imports alike; ``tests/test_layout.py``
enforces it, so a new module must be added to :data:`LAYERS`):

0. evaluation (pure: arrays and tables in, numbers out): ``triangulation``,
   ``restore``, ``metrics``, ``stats``, ``analysis``, ``sweep_stats``
1. running (configurations, scans, the run folder and its readers, the gate on
   saved runs, real photographs and their runs): ``config`` (and its ``profiles``), ``runio``, ``runfolder``,
   ``scan``, ``experiment``, ``renderahead``, ``gate``, ``real``, ``real_run``, ``sweep``
2. reporting (figures and the HTML reports from saved runs): ``figures``, ``report``, ``sweep_report``
3. studies (benchmarks on synthetic frames, tuning procedures): ``estimators``, ``perf``, ``tune``,
   ``translucency``
4. the command line: ``cli``, and ``gate_spread`` (runs the command line under machine
   configurations to derive the gate's tolerances)

``bench`` uses ``trackers`` (pixels only) and ``scenes`` (rendering); neither
of them imports ``bench``.
"""

LAYERS = {
    "evaluation": ("triangulation", "restore", "metrics", "stats", "analysis", "sweep_stats"),
    "running": ("config", "profiles", "runio", "runfolder", "scan", "experiment", "renderahead", "gate", "real",
                "real_run", "sweep"),
    "reporting": ("figures", "report", "sweep_report"),
    "studies": ("estimators", "perf", "tune", "translucency"),
    "cli": ("cli", "gate_spread"),
}
