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

import numpy as np

__all__ = ["study", "TARGET_RATIO"]

TARGET_RATIO = 1.3


def _config(lux: list[float], power: list[float], *, scene: str, material: str, size, angles: int, spp,
            trackers: str, repeats: int) -> str:
    w, h = size
    names = ", ".join(f'"{t}"' for t in trackers.split(","))
    return (f'name = "perf-sweep"\nseed = 0\ntrackers = [{names}]\nbaselines = []\ndp = []\nn_samples = 150\n'
            f'[render]\nwidth = {int(w)}\nheight = {int(h)}\n'
            + ('spp = "auto"\nambient_spp = "auto"\n' if spp == "auto" else f'spp = {spp}\n')
            + f'[[experiments]]\nscene = "{scene}"\nmaterial = "{material}"\nn_angles = {angles}\n'
            f'[sweep]\nambient_lux = {lux}\nlaser_power_mw = {power}\nrepeats = {repeats}\n')


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


def study(*, scene: str = "cone", material: str = "patchy", size=(256, 240), angles: int = 10, spp="auto",
          trackers=None, lux=(0.0, 100.0, 400.0, 1000.0, 2000.0), power=(1.0, 3.0, 10.0), repeats: int = 1,
          trials: int = 2, out=None) -> int:
    """Time a ``lux`` x ``power`` sweep grid against its single point (400 lux, 3 mW), each a fresh
    ``stripebench sweep`` process with a cold render cache (``stripebench perf sweep``).

    Parameters
    ----------
    scene, material : str
        The object and its material.
    size : (int, int)
        Width and height.
    angles : int
        Mirror angles.
    spp : "auto" or int
        Laser-pass samples per pixel (``"auto"``: the ambient pass's too).
    trackers : sequence of str or :class:`bench.config.TrackerSpec`, optional
        Plain tracker names (default threshold, centroid, dp4, dp8).
    lux, power : sequence of float
        The grid's ambient lux and laser powers (mW).
    repeats : int
        Repeats per grid point.
    trials : int
        Cold runs of each, alternated; the medians are compared.
    out : path, optional
        Where the sweeps go (default: a temporary folder).

    Returns
    -------
    int
        0, or 1 when the grid costs more than :data:`TARGET_RATIO` times the single point; the sweep
        configurations it writes are checked first.
    """
    from bench.config import parse
    from bench.config.options import plain_tracker_names
    from bench.config.sweep import parse_sweep

    trackers = ",".join(plain_tracker_names(trackers)) if trackers else "threshold,centroid,dp4,dp8"
    setup = {"scene": scene, "material": material, "size": size, "angles": angles, "spp": spp, "trackers": trackers,
             "repeats": repeats}
    lux, power = [float(x) for x in lux], [float(x) for x in power]  # TOML arrays
    import tomllib

    for grid in ((lux, power), ([400.0], [3.0])):  # both configurations, checked before any sweep runs
        doc = tomllib.loads(_config(*grid, **setup))
        table = doc.pop("sweep")
        parse_sweep(table, parse(doc))
    singles, grids = [], []
    with tempfile.TemporaryDirectory(prefix="stripebench-perf-sweep-") as tmp_s:
        tmp = Path(tmp_s)
        out = Path(out) if out else tmp / "out"
        for k in range(trials):
            singles.append(_timed_sweep(_config([400.0], [3.0], **setup), out, tmp, f"single{k}"))
            grids.append(_timed_sweep(_config(lux, power, **setup), out, tmp, f"grid{k}"))
    n = len(lux) * len(power)
    w1 = float(np.median([w for w, _ in singles]))
    wg = float(np.median([w for w, _ in grids]))
    ratio = wg / w1
    print(f"sweep cost, {scene}/{material} {size[0]}x{size[1]}, {angles} angles, spp {spp}, "
          f"trackers {trackers}, {repeats} repeat(s), cold render cache, sequential, fresh processes:")
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
