"""Speed of every registered tracker on a varied frame set (``stripebench perf``).

The frame set (:func:`bench.studies.perf.frames.varied_frames`, seeded) holds every
kind of frame the DP solver finds easy or hard: clean, noisy, long gaps and
cuts, bright blobs, bright ambient gradients, saturated wide stripes, two
stripes, large sideways jumps, saturated glint streaks; at 512x480, 960x600,
960x540 and 360x640. For each tracker: the median and the worst
ms per frame over the set, the median at 512x480 only, and for the DP
trackers the median ratio of MCP's time (same connectivity) to theirs. A frame's time is
the least of ``--repeats`` calls, by default in the calling thread's CPU
time (``--clock cpu``: on a shared machine wall time mostly measures the
other processes; ``--clock wall`` for an idle one).

The exact DP solver (:meth:`trackers.dp.DPTracker.path`: node costs, the
accumulated cost, backtracking) is timed on the same frames for 4- and
8-connectivity, at ``h_weight=1`` and at :data:`TARGET_H_WEIGHT`; skimage's
``MCP_Geometric`` solves the same isotropic graph (node cost ``1/(I+1)``, all
top-row starts, all bottom-row ends, then the traceback) on every
``--mcp-every``-th frame only (it is slow); the ratio is the median over those
frames of MCP's time over the solver's (and the least of those ratios, the
worst case, is reported beside it). The time of each tracker's first call
in a fresh process (numba's JIT compile with an empty cache, and the load
from the on-disk cache) is reported separately.

Targets (``--strict`` exits 1 if one is missed): the solver at
``h_weight=1`` and at :data:`TARGET_H_WEIGHT` (the trackers' default) at
least :data:`SOLVER_VS_MCP` times faster than MCP for both connectivities
(the median over the MCP frames of MCP's time over the solver's, MCP always
on its isotropic graph: the same frame solved by both); the solver at
:data:`TARGET_H_WEIGHT` at most :data:`H_WEIGHT_SLOWDOWN` times the
isotropic solve (medians); the trackers of :data:`MS_TARGETS` (``dp4`` and
``dp8`` among them) under their median ms at 512x480; :data:`RATIO_TARGETS`
relative to another tracker.

Instead of the synthetic set: your own frames with ``--frames`` (``.npy`` or
8-bit PNG files), or the photographs of a real set with ``--real [DIR]``
(default: the shipped set, frames as the trackers see them there).
"""

from __future__ import annotations

import json as _json  # `json` is an option of study()
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

from trackers.dp import DEFAULT_H_WEIGHT

__all__ = ["study", "frame_ms", "time_trackers", "time_solver", "time_mcp", "first_call_seconds", "MAX_REPEATS",
           "CLOCKS", "TARGET_H_WEIGHT", "SOLVER_VS_MCP", "H_WEIGHT_SLOWDOWN", "MS_TARGETS", "RATIO_TARGETS"]

#: The h_weight whose speed is checked against the isotropic solve: the DP
#: trackers' default (chosen by ``stripebench tune dp``).
TARGET_H_WEIGHT = DEFAULT_H_WEIGHT
#: Least speed-up of the exact solver over MCP_Geometric (median over frames), at
#: ``h_weight=1`` and at :data:`TARGET_H_WEIGHT`, for both connectivities.
SOLVER_VS_MCP = 100.0
#: Most slowdown of the solver at TARGET_H_WEIGHT over h_weight=1 (medians).
H_WEIGHT_SLOWDOWN = 1.5
#: Upper bounds in median ms per frame at 512x480 (``learned``: its inference budget, one core).
MS_TARGETS = {"threshold": 1.0, "centroid": 1.0, "gauss3": 1.0, "parabolic": 1.0, "blais_rioux": 1.0, "com_bg": 1.0,
              "steger": 20.0, "dp4": 1.0, "dp8": 1.0, "dp_gap": 1.0, "learned": 20.0}
#: Upper bounds as multiples of another tracker's median time in the same run.
RATIO_TARGETS = {"dp8_subpixel": ("dp8", 1.5)}


#: Clocks for :func:`frame_ms`: the calling thread's CPU time (work done,
#: least disturbed on a shared machine) or wall time.
CLOCKS = {"cpu": time.thread_time, "wall": time.perf_counter}


def frame_ms(fn, frames, repeats: int = 3, clock: str = "cpu") -> np.ndarray:
    """Milliseconds of ``fn(frame)`` for each frame: the least of ``repeats``
    calls (one untimed warm-up call first: JIT and caches), on ``clock``
    (``"cpu"``: this thread's CPU time; ``"wall"``: wall time)."""
    if clock not in CLOCKS:
        raise ValueError(f"`clock` must be one of 'cpu', 'wall', got {clock!r}")
    now = CLOCKS[clock]
    fn(frames[0])
    out = np.empty(len(frames))
    for k, f in enumerate(frames):
        best = np.inf
        for _ in range(repeats):
            t0 = now()
            fn(f)
            best = min(best, now() - t0)
        out[k] = 1e3 * best
    return out


def time_trackers(names, frames, repeats: int = 3, clock: str = "cpu") -> dict[str, np.ndarray]:
    """Per-frame milliseconds of ``track()`` for each tracker name."""
    import trackers

    return {name: frame_ms(trackers.make(name).track, frames, repeats, clock) for name in names}


def time_solver(frames, connectivity: int, h_weight: float, repeats: int = 3, clock: str = "cpu") -> np.ndarray:
    """Per-frame milliseconds of the exact DP solver (``DPTracker.path``)."""
    import trackers

    t = trackers.make("dp8" if connectivity == 8 else "dp4", h_weight=h_weight)
    return frame_ms(t.path, frames, repeats, clock)


def time_mcp(frames, connectivity: int, repeats: int = 1, clock: str = "cpu") -> np.ndarray:
    """Per-frame milliseconds of skimage MCP_Geometric on the isotropic DP graph."""
    from skimage.graph import MCP_Geometric

    def solve(img):
        cost = 1.0 / (img.astype(np.float64) + 1.0)
        H, W = cost.shape
        m = MCP_Geometric(cost, fully_connected=connectivity == 8)
        costs, _ = m.find_costs([(0, j) for j in range(W)], [(H - 1, j) for j in range(W)])
        return m.traceback((H - 1, int(np.argmin(costs[-1]))))

    return frame_ms(solve, frames, repeats, clock)


def first_call_seconds(name: str, cache_dir: str | None) -> float:
    """Seconds of the first ``track()`` in a fresh process (JIT or cache load).

    ``cache_dir=None`` uses the normal numba cache; a path uses that
    directory as numba's cache (an empty one measures a cold compile).
    """
    code = (
        "import time, numpy as np, trackers\n"
        f"t = trackers.make({name!r}); img = np.zeros((48, 64), np.uint8); img[:, 30] = 200\n"
        "t0 = time.perf_counter(); t.track(img); print(time.perf_counter() - t0)\n"
    )
    env = dict(os.environ)
    if cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = cache_dir
    root = pathlib.Path(__file__).resolve().parents[3]
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=root, check=True)
    return float(out.stdout.strip().splitlines()[-1])


def _load_frames(paths) -> list[tuple[str, np.ndarray]]:
    """``(name, 2-D frame)`` of each ``.npy`` or image file (:class:`bench.config.ConfigError` if one is unreadable)."""
    from bench.config import ConfigError
    from bench.store import realset

    frames = []
    for p in paths:
        p = pathlib.Path(p)
        if p.suffix == ".npy":
            try:
                img = np.load(p, allow_pickle=False)
            except (OSError, ValueError) as exc:
                raise ConfigError(f"--frames: cannot read {str(p)!r} as a .npy array ({exc})") from None
        else:
            try:
                img = realset.read_image(p)
            except realset.ImageError as exc:
                raise ConfigError(f"--frames: {exc}") from None
            img = img if img.ndim == 2 else img[..., 0]
        if img.ndim != 2 or min(img.shape, default=0) < 2 or not np.issubdtype(img.dtype, np.number):
            raise ConfigError(f"--frames: {str(p)!r} must hold a 2-D numeric frame, got shape {img.shape}")
        frames.append((p.name, img))
    return frames


def _fmt(v, spec):
    return format(v, spec) if v is not None else "-"


MAX_REPEATS = 1000  # --per-kind, --repeats, --mcp-every


def study(*, trackers=None, frames=None, per_kind: int = 2, seed: int = 0, repeats: int = 3, mcp_every: int = 4,
          clock: str = "cpu", real=None, no_jit: bool = False, strict: bool = False, json=None) -> int:
    """Time every tracker and the exact solver against MCP, print the figures and the verdicts
    (``stripebench perf trackers``).

    Parameters
    ----------
    trackers : sequence of str or :class:`bench.config.TrackerSpec`, optional
        Plain tracker names (default: every registered tracker).
    frames : list of path, optional
        Time on these frames (``.npy`` or PNG) instead of the synthetic set.
    per_kind : int
        Synthetic frames per kind and size (:func:`bench.studies.perf.frames.varied_frames`).
    seed : int
        Seed of the synthetic frames.
    repeats : int
        Calls per frame; the least counts.
    mcp_every : int
        Time MCP on every n-th frame.
    clock : str
        ``"cpu"`` (this thread's CPU time) or ``"wall"`` (:data:`CLOCKS`).
    real : str, optional
        Time on the frames of a real set (``""``: the shipped ``bench/data/real``).
    no_jit : bool
        Skip the first-call (JIT) measurements.
    strict : bool
        Return 1 if a target is missed.
    json : path, optional
        Also write the figures as JSON.

    Returns
    -------
    int
        0, or 1 with ``strict`` when a target is missed; bad inputs raise
        :class:`bench.config.ConfigError` first.
    """
    import trackers as registry  # `trackers` is the option

    from bench.config import ConfigError
    from bench.config.options import plain_tracker_names
    from bench.studies.perf.frames import varied_frames

    names = registry.available() if not trackers else plain_tracker_names(trackers)
    if frames and real is not None:
        raise ConfigError("give --frames or --real, not both")
    if json is not None and pathlib.Path(json).exists() and not pathlib.Path(json).is_file():
        raise ConfigError(f"--json must name a file, got {str(json)!r}")
    if real is not None:
        from bench.store import realset

        try:
            labelled = [(im.name, im.load()[0]) for im in realset.load_dataset(real or realset.SHIPPED)]
        except realset.DatasetError as exc:
            raise ConfigError(f"--real: {exc}") from None
    else:
        labelled = _load_frames(frames) if frames else varied_frames(per_kind, seed=seed)
    frames = [f for _, f in labelled]
    small = np.array([f.shape == (480, 512) for f in frames])
    sizes = sorted({f"{f.shape[1]}x{f.shape[0]}" for f in frames})
    print(f"stripebench perf: {len(frames)} frame(s) ({', '.join(sizes)}), least of {repeats} call(s) per "
          f"frame, {clock} time; MCP_Geometric on frames 0, {mcp_every}, {2 * mcp_every}, ... "
          f"({os.cpu_count()} cores)", flush=True)

    solver = {}
    for conn in (4, 8):
        for hw in (1.0, TARGET_H_WEIGHT):
            solver[conn, hw] = time_solver(frames, conn, hw, repeats, clock)
    sub = np.arange(0, len(frames), mcp_every)
    mcp = {conn: time_mcp([frames[k] for k in sub], conn, 1, clock) for conn in (4, 8)}
    ms = time_trackers(names, frames, repeats, clock)
    jit = {}
    if not no_jit:
        with tempfile.TemporaryDirectory() as empty:
            for n in names:
                jit[n] = (first_call_seconds(n, os.path.join(empty, n)), first_call_seconds(n, None))

    def med_small(a):
        return float(np.median(a[small])) if small.any() else None

    print(f"{'tracker':<14}{'median ms':>10}{'worst ms':>10}{'512x480 ms':>12}{'x MCP':>8}{'1st call cold s':>17}"
          f"{'1st call cached s':>19}")
    rows = []
    for n in names:
        a = ms[n]
        conn = getattr(registry.make(n), "connectivity", None)  # the DP trackers: against MCP on their graph
        ratio = float(np.median(mcp[conn] / a[sub])) if conn in mcp else None
        r = {"tracker": n, "median_ms": float(np.median(a)), "worst_ms": float(a.max()), "median_ms_512x480": med_small(a),
             "speedup_vs_mcp": ratio,
             "first_call_cold_s": jit.get(n, (None, None))[0], "first_call_cached_s": jit.get(n, (None, None))[1]}
        rows.append(r)
        print(f"{n:<14}{r['median_ms']:>10.3f}{r['worst_ms']:>10.2f}{_fmt(r['median_ms_512x480'], '.3f'):>12}"
              f"{_fmt(ratio, '.0f'):>8}{_fmt(r['first_call_cold_s'], '.2f'):>17}"
              f"{_fmt(r['first_call_cached_s'], '.2f'):>19}")
    print(f"{'exact solver':<24}{'median ms':>10}{'worst ms':>10}{'MCP ms (median)':>17}{'x MCP (median)':>16}"
          f"{'x MCP (worst)':>15}")
    solver_rows = []
    for (conn, hw), a in solver.items():
        ratio = float(np.median(mcp[conn] / a[sub]))
        worst = float(np.min(mcp[conn] / a[sub]))  # the frame where the solver gains least over MCP
        r = {"connectivity": conn, "h_weight": hw, "median_ms": float(np.median(a)), "worst_ms": float(a.max()),
             "mcp_median_ms": float(np.median(mcp[conn])), "speedup_vs_mcp": ratio, "speedup_vs_mcp_worst": worst}
        solver_rows.append(r)
        label = f"{conn}-conn, h_weight={hw:g}"
        print(f"{label:<24}{r['median_ms']:>10.3f}{r['worst_ms']:>10.2f}{r['mcp_median_ms']:>17.1f}{ratio:>16.0f}"
              f"{worst:>15.0f}")
    per_kind = {}
    for (conn, hw), a in solver.items():
        for (label, _), t in zip(labelled, a):
            per_kind.setdefault(label, {})[f"{conn}/{hw:g}"] = float(t)

    verdicts = []  # (text, ok)
    for conn in (4, 8):
        for hw in (1.0, TARGET_H_WEIGHT):
            ratio = float(np.median(mcp[conn] / solver[conn, hw][sub]))
            text = f"solver {conn}-conn h_weight={hw:g}: {ratio:.0f}x MCP (target >= {SOLVER_VS_MCP:g}x)"
            verdicts.append((text, ratio >= SOLVER_VS_MCP))
        slow = float(np.median(solver[conn, TARGET_H_WEIGHT]) / np.median(solver[conn, 1.0]))
        verdicts.append((f"solver {conn}-conn h_weight={TARGET_H_WEIGHT:g}: {slow:.2f}x the isotropic solve "
                         f"(target <= {H_WEIGHT_SLOWDOWN:g}x)", slow <= H_WEIGHT_SLOWDOWN))
    for r in rows:
        limit = MS_TARGETS.get(r["tracker"])
        if limit is not None and r["median_ms_512x480"] is not None:
            verdicts.append((f"{r['tracker']} {r['median_ms_512x480']:.3f} ms median at 512x480 "
                             f"(target <= {limit:g} ms)", r["median_ms_512x480"] <= limit))
        ref, factor = RATIO_TARGETS.get(r["tracker"], (None, None))
        if ref in ms:
            ratio = float(np.median(ms[r["tracker"]]) / np.median(ms[ref]))
            verdicts.append((f"{r['tracker']} {ratio:.2f}x {ref} (target <= {factor:g}x)", ratio <= factor))
    for text, ok in verdicts:
        print(f"  {text}: {'met' if ok else 'MISSED'}")
    if json:
        pathlib.Path(json).write_text(_json.dumps(
            {"frames": [label for label, _ in labelled], "mcp_frames": sub.tolist(), "trackers": rows,
             "solver": solver_rows, "solver_ms_per_frame": per_kind,
             "verdicts": [{"text": t, "met": ok} for t, ok in verdicts]}, indent=2))
    missed = sum(not ok for _, ok in verdicts)
    if strict and missed:
        print(f"stripebench perf: {missed} target(s) missed", file=sys.stderr)
        return 1
    return 0
