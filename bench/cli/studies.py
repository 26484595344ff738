"""The study commands: ``estimators``, ``translucency``, ``tune``, ``spread``, ``perf {trackers,scenes,sweep,shiny,sampling,lit,mis}``.

Each study keeps its options and its work in its own module
(:mod:`bench.studies`: ``add_arguments(parser)`` and ``command(args)``, from which
its ``main(argv)`` for ``python -m`` is built too); here they are only placed in
the command tree. A study module is imported only when its command is used.
"""

from __future__ import annotations

import importlib

from bench.cli.common import Command, description_of

__all__ = ["COMMANDS"]


def _study(module: str, name: str, help: str, *, renders: bool = False, **kw) -> Command:
    def add_arguments(parser):
        importlib.import_module(module).add_arguments(parser, **kw)

    def run(args):
        return importlib.import_module(module).command(args)

    return Command(name, help, add_arguments, run, description=description_of(module), renders=renders)


PERF = (
    _study("bench.studies.perf.trackers", "trackers", "speed of every tracker on a varied frame set (the default)"),
    _study("bench.studies.perf.scenes", "scenes", "rendering speed of the scenes", renders=True),
    _study("bench.studies.perf.sweep", "sweep", "cost of a scale-only sweep grid against its single point",
           renders=True),
    _study("bench.studies.perf.shiny", "shiny", "laser-pass integrators on shiny materials: noise and cost",
           renders=True),
    _study("bench.studies.perf.sampling", "sampling",
           "choose each material's integrator and sample counts by the render noise (spp = \"auto\")",
           renders=True),
    _study("bench.studies.perf.lit", "lit", "check that Scene.lit_pixels holds every pixel with direct laser light",
           renders=True),
    _study("bench.studies.perf.mis", "mis",
           "shiny objects' bounce light by camera and light paths with MIS, against their own pass", renders=True),
)

COMMANDS = (
    _study("bench.studies.estimators", "estimators", "the sub-pixel estimator study on analytic stripes"),
    _study("bench.studies.translucency", "translucency", "the subsurface-scattering bias study", renders=True),
    _study("bench.studies.tune", "tune", "choose a default by its committed procedure: `tune dp` (the DP's h_weight)",
           renders=True),
    _study("bench.studies.gate_spread", "spread",
           "the gated metrics' spread across machine configurations, and the gate's tolerances from it",
           renders=True),
    Command("perf", "speed benchmarks: `perf` (= `perf trackers`), `perf scenes`, `perf sweep`, `perf shiny`, `perf sampling`, `perf lit`, `perf mis`",
            lambda parser: parser.add_argument("--strict", action="store_true",
                                               help="with no WHAT: `perf trackers --strict` (exit 1 if a target "
                                                    "is missed)"), None,
            description="Speed benchmarks; `stripebench perf` alone runs `stripebench perf trackers`.",
            subcommands=PERF, default_subcommand="trackers"),
)
