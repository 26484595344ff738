"""The study commands: ``estimators``, ``translucency``, ``tune``, ``loro``, ``spread``, ``perf {trackers,scenes,sweep,shiny,sampling,lit,mis}``.

Each command's options are defined here (``tune``: :mod:`bench.cli.tune`, ``perf``:
:mod:`bench.cli.perf`); its work is a study's plain function (``study(...)`` of its module
in :mod:`bench.studies`), called with them (:func:`bench.cli.common.study_command`). A study
module is imported only when its command is used. Two studies run outside the tree, each by
its own entry point: :data:`TRANSLUCENCY_PROFILE` (``python -m bench.cli.translucency_profile``)
and :data:`FIELD_SHEET` (``python -m bench.cli.field_sheet``); ``python -m bench.cli.gate_spread``
is the older name of ``stripebench spread``.
"""

from __future__ import annotations

from pathlib import Path

from bench.cli import perf, tune
from bench.cli.common import study_command
from bench.cli.options import add_out, add_quiet, add_seed, add_trackers, arg_type
from bench.config.options import finite_float, finite_floats, positive_int, width16_value

__all__ = ["COMMANDS", "SPREAD", "TRANSLUCENCY_PROFILE", "FIELD_SHEET"]


def estimators_options(parser) -> None:
    """The options of ``stripebench estimators``."""
    from bench.studies.estimators import BACKGROUND_DN, DEFAULTS, MAX_FRAMES

    def floats(low_open):
        return lambda name, text: finite_floats(name, text, low=0, low_open=low_open)

    add_out(parser, "output folder", default=DEFAULTS["out"])
    parser.add_argument("--sigmas", type=arg_type(floats(True), "--sigmas"), default=DEFAULTS["sigmas"],
                        metavar="LIST", help="stripe sigmas in px, comma-separated, finite and > 0")
    parser.add_argument("--peaks", type=arg_type(floats(True), "--peaks"), default=DEFAULTS["peaks"], metavar="LIST",
                        help=f"peak levels in DN above {BACKGROUND_DN:g} DN, finite and > 0")
    parser.add_argument("--noises", type=arg_type(floats(False), "--noises"), default=DEFAULTS["noises"],
                        metavar="LIST", help="noise sigmas in DN, finite and >= 0")
    parser.add_argument("--frames", type=arg_type(lambda n, v: positive_int(n, v, MAX_FRAMES), "--frames"),
                        default=DEFAULTS["frames"], metavar="N",
                        help=f"64-row frames per cell (1 .. {MAX_FRAMES}; default {DEFAULTS['frames']})")
    add_seed(parser, "seed of the frames", default=DEFAULTS["seed"])
    add_trackers(parser, "comma-separated tracker names (default: every sub-pixel tracker)")
    parser.add_argument("--plot-peak", type=arg_type(lambda n, v: finite_float(n, v, low=0, low_open=True),
                                                     "--plot-peak"),
                        metavar="DN", help="peak level plotted (default: the middle one)")
    parser.add_argument("--no-plot", action="store_true", help="write the table only")


def _scene_set_options(parser, defaults, objects_value, materials_value, materials_what: str, max_angles: int,
                       angles_help: str, size_note: str) -> None:
    """The options of a study over objects x materials at a few angles: ``--out``, ``--objects``,
    ``--materials``, ``--angles``, ``--size`` (``defaults``: the study's ``DEFAULTS``)."""
    add_out(parser, "output folder", default=defaults["out"])
    parser.add_argument("--objects", type=arg_type(objects_value, "--objects"),
                        default=defaults["objects"], metavar="LIST",
                        help=f"comma-separated objects (default {','.join(defaults['objects'])})")
    parser.add_argument("--materials", type=arg_type(materials_value, "--materials"),
                        default=defaults["materials"], metavar="LIST",
                        help=f"comma-separated {materials_what} (default {','.join(defaults['materials'])})")
    parser.add_argument("--angles", type=arg_type(lambda n, v: positive_int(n, v, max_angles), "--angles"),
                        default=defaults["angles"], metavar="N", help=angles_help)
    parser.add_argument("--size", type=arg_type(width16_value, "--size"), default=defaults["size"], metavar="PX",
                        help=f"image width, px, a multiple of 16 ({size_note}default {defaults['size']})")


def translucency_options(parser) -> None:
    """The options of ``stripebench translucency``."""
    from bench.studies.translucency import DEFAULTS, MAX_ANGLES, materials_value, objects_value, spp_count, spp_list

    _scene_set_options(parser, DEFAULTS, objects_value, materials_value, "materials", MAX_ANGLES,
                       f"mirror angles per object (1 .. {MAX_ANGLES}; default {DEFAULTS['angles']})",
                       "height = 15/16 of it; ")
    parser.add_argument("--spp", type=arg_type(spp_count, "--spp"),
                        default=DEFAULTS["spp"], metavar="N",
                        help=f"laser-pass samples per pixel (default {DEFAULTS['spp']})")
    add_seed(parser, "seed of the renders and the noise", default=DEFAULTS["seed"])
    add_trackers(parser, "comma-separated tracker names (default: every sub-pixel tracker)")
    parser.add_argument("--plot-tracker", default=DEFAULTS["plot_tracker"], metavar="NAME",
                        help=f"tracker of the bias panel (default {DEFAULTS['plot_tracker']})")
    parser.add_argument("--spp-study", type=arg_type(spp_list, "--spp-study"), metavar="SPPS",
                        help="also measure render noise vs these spp (e.g. 16,64,256) on the first object, every material")
    parser.add_argument("--skip-study", action="store_true", help="with --spp-study: only the render-noise study")
    add_quiet(parser)


def spread_options(parser) -> None:
    """The options of ``stripebench spread``."""
    from bench.studies.gate_spread import MACHINES, SAFETY

    parser.add_argument("--out", type=Path, required=True, help="folder for the runs, their caches and spread.json")
    parser.add_argument("--gates", default="ci,real", help="comma-separated gates (ci, real)")
    parser.add_argument("--machines", default=",".join(m.name for m in MACHINES),
                        help=f"comma-separated machines (default all: {', '.join(m.name for m in MACHINES)})")
    parser.add_argument("--safety", type=float, default=SAFETY, help=f"factor on the spread (default {SAFETY:g})")
    parser.add_argument("--reuse", action="store_true",
                        help="read the runs already finished in --out (same machines) instead of running them again")
    parser.add_argument("--write", type=Path, metavar="DIR",
                        help="write DIR/ci.json and DIR/real.json from the reference runs with the derived tolerances")
    parser.add_argument("--against", type=Path, metavar="FILE", action="append", default=[],
                        help="a baseline another machine wrote for the one gate measured (same renderer; "
                             "repeatable): its entries that move more than their metric's tolerance get their own")


def translucency_profile_options(parser) -> None:
    """The options of ``python -m bench.cli.translucency_profile``."""
    from bench.studies.translucency_profile import DEFAULTS, materials_value, objects_value, seeds_value

    _scene_set_options(parser, DEFAULTS, objects_value, materials_value, "translucent materials", 1000,
                       f"mirror angles per case (default {DEFAULTS['angles']})", "")
    parser.add_argument("--seeds", type=arg_type(seeds_value, "--seeds"), default=DEFAULTS["seeds"], metavar="A,B",
                        help="the two render seeds (default 1,2; the paper run's is 0)")
    parser.add_argument("--single-scatter", action="store_true",
                        help="instead: volpath's single scattering on turned boards against Chandrasekhar's")
    add_quiet(parser)


def field_sheet_options(parser) -> None:
    """The options of ``python -m bench.cli.field_sheet``."""
    parser.add_argument("out", type=Path, help="PNG file to write")
    parser.add_argument("--cost", action="store_true", help="also print each experiment's render cost per frame")


#: ``stripebench spread`` (also ``python -m bench.cli.gate_spread``, its older name).
SPREAD = study_command("spread", "the gated metrics' spread across machine configurations, and the gate's tolerances "
                                 "from it", spread_options, "bench.studies.gate_spread:study", renders=True)

def loro_options(parser) -> None:
    """The options of ``stripebench loro``."""
    from bench.studies.loro import DEFAULT_OUT, DEFAULT_TUNING

    def names(name, text):
        import trackers

        known = trackers.available(unlisted=True)
        out = [t.strip() for t in text.split(",") if t.strip()]
        bad = [t for t in out if t not in known]
        if not out or bad:
            raise ValueError(f"{name}: unknown tracker(s) {', '.join(bad) or '(none given)'} "
                             f"(known: {', '.join(known)})")
        return out

    parser.add_argument("--dataset", type=Path, default=None, metavar="DIR",
                        help="real set whose manifest names each photograph's rig (default: the shipped one)")
    parser.add_argument("--threshold", type=Path, default=DEFAULT_TUNING["threshold"], metavar="JSON",
                        help=f"summary.json of `stripebench tune threshold` (default {DEFAULT_TUNING['threshold']})")
    parser.add_argument("--gap", type=Path, default=DEFAULT_TUNING["dp_gap"], metavar="JSON",
                        help=f"summary.json of `stripebench tune dp_gap` (default {DEFAULT_TUNING['dp_gap']})")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, metavar="CSV", help=f"the table (default {DEFAULT_OUT})")
    parser.add_argument("--trackers", type=arg_type(names, "--trackers"), metavar="LIST",
                        help="comma-separated tracker names (default: every listed tracker)")
    add_quiet(parser, "no progress lines")


COMMANDS = (
    study_command("estimators", "the sub-pixel estimator study on analytic stripes", estimators_options,
                  "bench.studies.estimators:study"),
    study_command("translucency", "the subsurface-scattering bias study", translucency_options,
                  "bench.studies.translucency:study", renders=True),
    tune.COMMAND,
    study_command("loro", "the default trackers on photographs leave one rig out, from the tuning procedures' "
                          "choices: results/real_loro.csv", loro_options, "bench.studies.loro:study"),
    SPREAD,
    perf.COMMAND,
)

#: ``python -m bench.cli.translucency_profile``: the fast translucent path against the reference (not in the tree).
TRANSLUCENCY_PROFILE = study_command("translucency_profile", "the fast translucent path against the reference",
                                     translucency_profile_options, "bench.studies.translucency_profile:study",
                                     renders=True)
#: ``python -m bench.cli.field_sheet``: the field profile's conditions at a glance (not in the tree).
FIELD_SHEET = study_command("field_sheet", "the field profile's conditions at a glance", field_sheet_options,
                            "bench.studies.field_sheet:sheet", renders=True,
                            description="The field profile's conditions at a glance, and what each costs to render.")
