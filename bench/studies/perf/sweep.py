"""Cost of a scale-only sweep grid against its single point, cold render cache.

Usage: ``python -m bench.studies.perf.sweep [--scene cone] [--material patchy] [--size 256x240] [--angles 10]
[--spp 16] [--trackers threshold,centroid,dp4,dp8] [--lux 0,100,400,1000,2000] [--power 1,3,10]
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

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

__all__ = ["main", "TARGET_RATIO"]

TARGET_RATIO = 1.3


def _config(args, lux: list[float], power: list[float]) -> str:
    w, h = args.size.split("x")
    trackers = ", ".join(f'"{t}"' for t in args.trackers.split(","))
    return (f'name = "perf-sweep"\nseed = 0\ntrackers = [{trackers}]\nbaselines = []\ndp = []\nn_samples = 150\n'
            f'[render]\nwidth = {int(w)}\nheight = {int(h)}\nspp = {args.spp}\n'
            f'[[experiments]]\nscene = "{args.scene}"\nmaterial = "{args.material}"\nn_angles = {args.angles}\n'
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


def main(argv: Optional[Sequence[str]] = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m bench.studies.perf.sweep", description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="cone")
    ap.add_argument("--material", default="patchy")
    ap.add_argument("--size", default="256x240", help="WIDTHxHEIGHT (16:15)")
    ap.add_argument("--angles", type=int, default=10)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--trackers", default="threshold,centroid,dp4,dp8")
    ap.add_argument("--lux", default="0,100,400,1000,2000")
    ap.add_argument("--power", default="1,3,10")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--trials", type=int, default=2, help="cold runs of each, alternated; the medians are compared")
    ap.add_argument("--out", type=Path, default=None, help="where the sweeps go (default: a temporary folder)")
    args = ap.parse_args(argv)
    lux = [float(x) for x in args.lux.split(",")]
    power = [float(x) for x in args.power.split(",")]
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
    print(f"sweep cost, {args.scene}/{args.material} {args.size}, {args.angles} angles, spp {args.spp}, "
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


if __name__ == "__main__":
    raise SystemExit(main())
