"""Cost of a scale-only sweep grid against its single point, cold render cache.

Usage: ``stripebench perf sweep [--scene cone] [--material patchy] [--size 256x240] [--angles 10]
[--spp auto|N] [--trackers threshold,centroid,dp4,dp8] [--lux 0,100,400,1000,2000] [--power 1,3,10]
[--repeats 1] [--trials 2] [--out DIR]``

Runs ``stripebench sweep --scheduler sync``, each time in a fresh Python process
with its own empty render cache (``STRIPEBENCH_CACHE_DIR`` in a temporary
folder), on the single point (400 lux, 3 mW) and on the lux x power grid,
alternated ``--trials`` times (this machine is shared: medians are compared).
Prints the wall times, the ratio of the medians (target: <= 1.3x, since the grid needs no new
renders) and the measured per-unit costs (render s per frame, evaluation ms per
frame x grid point x repeat) that ``docs/sweeps.md`` uses for sizing.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

__all__ = ["add_arguments", "command", "main", "TARGET_RATIO"]

TARGET_RATIO = 1.3


def _config(args, lux: list[float], power: list[float]) -> str:
    w, h = args.size
    trackers = ", ".join(f'"{t}"' for t in args.trackers.split(","))
    return (f'name = "perf-sweep"\nseed = 0\ntrackers = [{trackers}]\nbaselines = []\ndp = []\nn_samples = 150\n'
            f'[render]\nwidth = {int(w)}\nheight = {int(h)}\n'
            + ('spp = "auto"\nambient_spp = "auto"\n' if args.spp == "auto" else f'spp = {args.spp}\n')
            + f'[[experiments]]\nscene = "{args.scene}"\nmaterial = "{args.material}"\nn_angles = {args.angles}\n'
            f'[sweep]\nambient_lux = {lux}\nlaser_power_mw = {power}\nrepeats = {args.repeats}\n')


def _timed_sweep(config_text: str, out: Path, tmp: Path, label: str) -> tuple[float, dict]:
    cfg = tmp / f"{label}.toml"
    cfg.write_text(config_text)
    cache = tmp / f"cache-{label}"
    env = {**os.environ, "STRIPEBENCH_CACHE_DIR": str(cache)}
    repo = Path(__file__).resolve().parents[3]
    env["PYTHONPATH"] = str(repo) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "bench.cli", "sweep", str(cfg), "--out", str(out / label),
                           "--scheduler", "sync", "--quiet"], env=env, cwd=repo, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"sweep {label} failed ({proc.returncode}): {proc.stderr.strip()[-2000:]}")
    from bench.store.sweepfiles import load_sweep

    summary = load_sweep(out / label)["summary"]
    return wall, summary


def add_arguments(parser) -> None:
    """The benchmark's options (``stripebench perf sweep``)."""
    from bench.config.options import add_trackers, arg_type, finite_floats, positive_int, size_value, spp_value

    def nonneg(name):
        return arg_type(lambda n, v: finite_floats(n, v, low=0), name)

    parser.add_argument("--scene", default="cone", help="the object (default cone)")
    parser.add_argument("--material", default="patchy", help="its material (default patchy)")
    parser.add_argument("--size", type=arg_type(size_value, "--size"), default=(256, 240), metavar="WxH",
                        help="WIDTHxHEIGHT (16:15; default 256x240)")
    parser.add_argument("--angles", type=arg_type(lambda n, v: positive_int(n, v, 10000), "--angles"), default=10,
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
    parser.add_argument("--repeats", type=arg_type(lambda n, v: positive_int(n, v, 1000), "--repeats"), default=1,
                        metavar="N", help="repeats per grid point (default 1)")
    parser.add_argument("--trials", type=arg_type(lambda n, v: positive_int(n, v, 100), "--trials"), default=2,
                        metavar="N", help="cold runs of each, alternated; the medians are compared (default 2)")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="where the sweeps go (default: a temporary folder)")


def command(args) -> int:
    """Run the benchmark with parsed options (the sweep configurations it writes are checked first)."""
    from bench.config import parse
    from bench.config.options import plain_tracker_names
    from bench.config.sweep import parse_sweep

    args.trackers = ",".join(plain_tracker_names(args.trackers)) if args.trackers else "threshold,centroid,dp4,dp8"
    lux, power = args.lux, args.power
    import tomllib

    for grid in ((lux, power), ([400.0], [3.0])):  # both configurations, checked before any sweep runs
        doc = tomllib.loads(_config(args, *grid))
        table = doc.pop("sweep")
        parse_sweep(table, parse(doc))
    singles, grids = [], []
    with tempfile.TemporaryDirectory(prefix="stripebench-perf-sweep-") as tmp_s:
        tmp = Path(tmp_s)
        out = args.out or tmp / "out"
        for k in range(args.trials):
            singles.append(_timed_sweep(_config(args, [400.0], [3.0]), out, tmp, f"single{k}"))
            grids.append(_timed_sweep(_config(args, lux, power), out, tmp, f"grid{k}"))
    n = len(lux) * len(power)
    w1 = float(np.median([w for w, _ in singles]))
    wg = float(np.median([w for w, _ in grids]))
    ratio = wg / w1
    print(f"sweep cost, {args.scene}/{args.material} {args.size[0]}x{args.size[1]}, {args.angles} angles, spp {args.spp}, "
          f"trackers {args.trackers}, {args.repeats} repeat(s), cold render cache, sequential, fresh processes:")
    print(f"  single point (400 lux, 3 mW): {w1:7.1f} s wall (median of {', '.join(f'{w:.1f}' for w, _ in singles)})")
    print(f"  grid: median of {', '.join(f'{w:.1f}' for w, _ in grids)} s")
    print(f"  {len(lux)} lux x {len(power)} power grid ({n} points): {wg:7.1f} s wall  -> {ratio:.2f}x the single "
          f"point (target <= {TARGET_RATIO}x): {'ok' if ratio <= TARGET_RATIO else 'MISSED'}")
    for label, runs in (("single", singles), ("grid", grids)):
        for k, (w, s) in enumerate(runs):
            for c in s["costs"]:
                print(f"  {label}{k}: wall {w:.1f} s; render {c['render_s_per_frame']:.3f} s per frame "
                      f"({c['frames']} frames, cold: scene load and JIT included; "
                      f"{c['render_s_per_later_frame']:.3f} s after the first), setup {c['setup_s']:.1f} s, "
                      f"evaluation {1e3 * c['eval_s_per_evaluation']:.1f} ms per frame x point x repeat "
                      f"({c['evaluations']}); sweep inside the process {s['wall_s']:.1f} s")
    return 0 if ratio <= TARGET_RATIO else 1


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m bench.studies.perf.sweep``: the same options as ``stripebench perf sweep``."""
    from bench.config.options import study_main

    return study_main("stripebench perf sweep", __doc__, add_arguments, command, argv)


if __name__ == "__main__":
    raise SystemExit(main())
