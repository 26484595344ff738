"""The ``perf`` command group: ``stripebench perf {trackers,scenes,sweep,shiny,sampling,lit,mis}``.

Each sub-command's options are defined here; its work is the plain function ``study(...)``
of its module in :mod:`bench.studies.perf`, called with them (a study module is imported
only when its command is parsed or run). ``stripebench perf`` alone runs ``perf trackers``.
"""

from __future__ import annotations

import pathlib

from bench.cli.common import Command, study_command
from bench.cli.options import add_seed, add_trackers, arg_type
from bench.config.options import finite_floats, int_in_range, positive_int, size_value, spp_value
from bench.errors import ConfigError

__all__ = ["PERF", "COMMAND"]


def _count(high: int, name: str):
    return arg_type(lambda n, v: positive_int(n, v, high), name)


def trackers_options(parser) -> None:
    """The options of ``stripebench perf trackers`` (``stripebench perf`` alone runs it with these defaults)."""
    from bench.studies.perf.trackers import CLOCKS, MAX_REPEATS

    add_trackers(parser, "comma-separated tracker names (default: all registered)")
    parser.add_argument("--frames", nargs="+", metavar="FILE", help="time on these frames (.npy or PNG)")
    parser.add_argument("--per-kind", type=_count(MAX_REPEATS, "--per-kind"), default=2, metavar="N",
                        help="synthetic frames per kind and size (default 2)")
    add_seed(parser, "seed of the synthetic frames", default=0)
    parser.add_argument("--repeats", type=_count(MAX_REPEATS, "--repeats"), default=3, metavar="N",
                        help="calls per frame, the least counts (default 3)")
    parser.add_argument("--mcp-every", type=_count(MAX_REPEATS, "--mcp-every"), default=4, metavar="N",
                        help="time MCP on every n-th frame (default 4)")
    parser.add_argument("--clock", choices=sorted(CLOCKS), default="cpu",
                        help="cpu: this thread's CPU time (default; robust on a shared machine), or wall")
    parser.add_argument("--real", nargs="?", const="", metavar="DIR",
                        help="time on the frames of a real set (default: the shipped bench/data/real)")
    parser.add_argument("--no-jit", action="store_true", help="skip the first-call (JIT) measurements")
    parser.add_argument("--strict", action="store_true", help="exit 1 if a target is missed")
    parser.add_argument("--json", type=pathlib.Path, metavar="FILE", help="also write the figures as JSON")


def scenes_options(parser) -> None:
    """The options of ``stripebench perf scenes``."""
    import scenes

    from bench.studies.perf.scenes import FRAME_VS_BARE, materials_value, object_value

    parser.add_argument("--object", type=arg_type(object_value, "--object"), default="hand",
                        help="the scanned object (default hand)")
    parser.add_argument("--frames", type=arg_type(lambda n, v: int_in_range(n, v, 0, 100000), "--frames"),
                        default=100, metavar="N", help="frames of the timed scan; 0 skips it (default 100)")
    parser.add_argument("--per-material", type=_count(1000, "--per-material"),
                        default=6, metavar="N", help="frames timed per material (default 6)")
    parser.add_argument("--materials", type=arg_type(materials_value, "--materials"), default=list(scenes.MATERIALS),
                        metavar="LIST", help="comma-separated materials (default: all; the translucent ones cost ~15x matte)")
    parser.add_argument("--spp", type=arg_type(spp_value, "--spp"), default="auto", metavar="auto|N",
                        help="laser-pass samples per pixel (default auto: scenes.sampling)")
    parser.add_argument("--ambient-spp", type=arg_type(spp_value, "--ambient-spp"), default="auto", metavar="auto|N",
                        help="ambient-pass samples per pixel (default auto)")
    parser.add_argument("--strict", action="store_true", help=f"exit 1 if frame / bare > {FRAME_VS_BARE}")
    parser.add_argument("--background", default="wall", choices=("wall", "none"))
    parser.add_argument("--support", default="none", choices=("none", "table"))


def sweep_options(parser) -> None:
    """The options of ``stripebench perf sweep``."""

    def nonneg(name):
        return arg_type(lambda n, v: finite_floats(n, v, low=0), name)

    parser.add_argument("--scene", default="cone", help="the object (default cone)")
    parser.add_argument("--material", default="patchy", help="its material (default patchy)")
    parser.add_argument("--size", type=arg_type(size_value, "--size"), default=(256, 240), metavar="WxH",
                        help="WIDTHxHEIGHT (16:15; default 256x240)")
    parser.add_argument("--angles", type=_count(10000, "--angles"), default=10,
                        metavar="N", help="mirror angles (default 10)")
    parser.add_argument("--spp", type=arg_type(spp_value, "--spp"),
                        default="auto", metavar="auto|N",
                        help="laser-pass samples per pixel, or auto (scenes.sampling; the ambient pass then too) "
                             "(default auto)")
    add_trackers(parser, "comma-separated tracker names (default threshold,centroid,dp4,dp8)")
    parser.add_argument("--lux", type=nonneg("--lux"), default=[0.0, 100.0, 400.0, 1000.0, 2000.0], metavar="LIST",
                        help="ambient lux of the grid (default 0,100,400,1000,2000)")
    parser.add_argument("--power", type=nonneg("--power"), default=[1.0, 3.0, 10.0], metavar="LIST",
                        help="laser powers, mW, of the grid (default 1,3,10)")
    parser.add_argument("--repeats", type=_count(1000, "--repeats"), default=1,
                        metavar="N", help="repeats per grid point (default 1)")
    parser.add_argument("--trials", type=_count(100, "--trials"), default=2,
                        metavar="N", help="cold runs of each, alternated; the medians are compared (default 2)")
    parser.add_argument("--out", type=pathlib.Path, default=None, metavar="DIR",
                        help="where the sweeps go (default: a temporary folder)")


def shiny_options(parser) -> None:
    """The options of ``stripebench perf shiny``."""
    from bench.studies.perf.shiny import CASES

    parser.add_argument("--size", type=arg_type(size_value, "--size"), default=(128, 120), metavar="WxH",
                        help="WIDTHxHEIGHT (default 128x120)")
    parser.add_argument("--spp", type=_count(65536, "--spp"), nargs="+", default=[4, 16], metavar="N",
                        help="spp of the compared renders (default 4 16)")
    parser.add_argument("--ref-spp", type=_count(65536, "--ref-spp"), default=4096, metavar="N",
                        help="spp of the reference (default 4096)")
    parser.add_argument("--cases", type=arg_type(lambda n, v: int_in_range(n, v, 0, len(CASES)), "--cases"),
                        default=len(CASES), metavar="N", help=f"the first N of CASES (0 .. {len(CASES)})")
    parser.add_argument("--mask", action="store_true", help="the false stripe's energy near the truth's mask")
    parser.add_argument("--sweep", type=arg_type(lambda n, v: int_in_range(n, v, 0, 10000), "--sweep"), default=0,
                        metavar="N", help="scan N default angles per shiny material")
    parser.add_argument("--support", default="none", choices=["none", "table"], help="for --mask and --sweep")
    parser.add_argument("--cost", action="store_true", help="also time Scene.render per frame at 512x480")
    parser.add_argument("--cost-spp", type=_count(65536, "--cost-spp"), default=None, metavar="N",
                        help="spp of --cost (default: the scene's)")


def sampling_options(parser) -> None:
    """The options of ``stripebench perf sampling``."""
    from bench.studies.perf.sampling import AMBIENT_ONLY, MATERIALS, REF_OBJECT_SPP

    parser.add_argument("--angles", type=arg_type(lambda n, v: int_in_range(n, v, 1, 9), "--angles"), default=2,
                        metavar="N", help="calibration angles per case (default 2)")
    parser.add_argument("--ref-spp", type=_count(65536, "--ref-spp"),
                        default=144, metavar="N", help="spp of the laser references (default 144)")
    parser.add_argument("--ref-ambient-spp", type=_count(65536, "--ref-ambient-spp"),
                        default=144, metavar="N", help="spp of the ambient references (default 144)")
    parser.add_argument("--ref-object-spp", type=_count(65536, "--ref-object-spp"),
                        default=REF_OBJECT_SPP, metavar="N",
                        help=f"spp of a shiny object's own reference, on its pixels (default {REF_OBJECT_SPP})")
    parser.add_argument("--materials", default=None, metavar="LIST",
                        help=f"comma-separated materials (default {','.join(MATERIALS + AMBIENT_ONLY)}; with --from, "
                             "those the file has)")
    parser.add_argument("--write", action="store_true", help="write the choices into scenes/sampling.py")
    parser.add_argument("--save", metavar="FILE", default=None,
                        help="also write the measurements (every candidate, every material) as JSON")
    parser.add_argument("--from", dest="from_file", metavar="FILE", default=None,
                        help="choose (and --write) from measurements saved by --save instead of rendering")


def lit_options(parser) -> None:
    """The options of ``stripebench perf lit``."""

    def sizes(name, text):
        out = [size_value(name, t) for t in str(text).split(",") if t.strip()]
        if not out:
            raise ConfigError(f"{name} must name at least one WIDTHxHEIGHT, got {text!r}")
        return out

    parser.add_argument("--sizes", type=arg_type(sizes, "--sizes"), default=[(128, 120), (256, 240), (512, 480)],
                        metavar="LIST", help="comma-separated image sizes (default 128x120,256x240,512x480)")
    parser.add_argument("--every", type=_count(100, "--every"), default=2,
                        metavar="K", help="every K-th default mirror angle (default 2)")
    parser.add_argument("--spp", type=_count(4096, "--spp"), default=16,
                        metavar="N", help="samples per pixel of the whole-image render (default 16)")


def mis_options(parser) -> None:
    """The options of ``stripebench perf mis``."""
    parser.add_argument("--materials", default="polished,glazed", metavar="LIST",
                        help="comma-separated shiny materials (default polished,glazed)")
    parser.add_argument("--objects", default="cone,hand", metavar="LIST",
                        help="comma-separated objects (default cone,hand)")
    parser.add_argument("--counts", default="4+2,8+2,8+4,16+2", metavar="LIST",
                        help="comma-separated camera+light counts (default 4+2,8+2,8+4,16+2)")
    parser.add_argument("--angles", type=arg_type(lambda n, v: int_in_range(n, v, 1, 9), "--angles"), default=2,
                        metavar="N", help="calibration angles per case (default 2)")
    parser.add_argument("--ref-object-spp", type=_count(65536, "--ref-object-spp"),
                        default=1024, metavar="N", help="spp of the object pass's reference (default 1024)")


PERF = (
    study_command("trackers", "speed of every tracker on a varied frame set (the default)", trackers_options,
                  "bench.studies.perf.trackers:study"),
    study_command("scenes", "rendering speed of the scenes", scenes_options, "bench.studies.perf.scenes:study",
                  renders=True),
    study_command("sweep", "cost of a scale-only sweep grid against its single point", sweep_options,
                  "bench.studies.perf.sweep:study", renders=True),
    study_command("shiny", "laser-pass integrators on shiny materials: noise and cost", shiny_options,
                  "bench.studies.perf.shiny:study", renders=True),
    study_command("sampling", "choose each material's integrator and sample counts by the render noise (spp = \"auto\")",
                  sampling_options, "bench.studies.perf.sampling:study", renders=True),
    study_command("lit", "check that Scene.lit_pixels holds every pixel with direct laser light", lit_options,
                  "bench.studies.perf.lit:study", renders=True),
    study_command("mis", "shiny objects' bounce light by camera and light paths with MIS, against their own pass",
                  mis_options, "bench.studies.perf.mis:study", renders=True),
)

#: ``stripebench perf [WHAT]``.
COMMAND = Command(
    "perf", "speed benchmarks: `perf` (= `perf trackers`), `perf scenes`, `perf sweep`, `perf shiny`, `perf sampling`, "
            "`perf lit`, `perf mis`",
    lambda parser: parser.add_argument("--strict", action="store_true",
                                       help="with no WHAT: `perf trackers --strict` (exit 1 if a target is missed)"),
    None, description="Speed benchmarks; `stripebench perf` alone runs `stripebench perf trackers`.",
    subcommands=PERF, default_subcommand="trackers")
