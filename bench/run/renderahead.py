"""Render-ahead: one helper process fills the render cache while a run tracks.

A run (:func:`bench.run.experiment.run`) renders and tracks its frames one after
another in one process, and parts of that leave a core idle on a 2-core
machine: the light-traced (``ptracer``) passes of ``specular``, ``polished`` and
``glazed`` run on one drjit thread on purpose (bit-reproducibility, see
:mod:`scenes.backend`), and the Python parts (truth, sensor noise, trackers,
cache writes) run on one core. :class:`RenderAhead` starts ONE Dask worker
process (:func:`bench.run.cluster.local_cluster`, one single-threaded worker)
that renders the run's frames into the render cache (:mod:`scenes.cache`) in
reverse order, the last experiment's last frame first, skipping frames already
there, while the run goes through its experiments in order exactly as without
it. A frame the helper rendered is a cache hit for the run.

* **Results do not change.** A frame's unit renders are a pure function of its
  arguments, whatever drjit's thread count (light-traced passes run on one
  thread in either process), and a cache file is written to a temporary name
  and renamed (:func:`scenes.cache.store`), so the run never reads half a file.
* **The helper only takes idle time.** Its threads run at the lowest
  scheduling priority (:data:`NICE`), so the run's own threads (and anyone
  else's) get the cores first; the helper renders while the run leaves a core
  idle (one-threaded light tracing, the Python parts).
* **The helper follows the run.** The run publishes the (flattened) index of
  the frame it is about to render in a Dask ``Variable``; before each frame the
  helper reads it and stops when its next frame is not more than :data:`MARGIN`
  frames after the run's (the two have met: the run renders the rest).
* **Nothing is left running.** When the run's loop ends, or on an error or
  KeyboardInterrupt, :meth:`RenderAhead.stop` moves the published position past
  the end and, unless the helper has already stopped by itself, kills the
  worker process at once (the frame it is rendering is one the run no longer
  needs; the cache file is written to a temporary name, so at worst a
  ``.tmp-*.npz`` file is left in the cache folder), then closes the cluster:
  about a second.
* **When.** On by default when the machine has at least 2 cores, the
  configuration has at least 2 experiments, every experiment uses the render
  cache (:func:`reason_off`), and the frames not cached yet hold at least
  :data:`MIN_PIXEL_SAMPLES` pixel-samples (:meth:`RenderAhead.start`); off with the
  configuration key ``render_ahead = false`` or ``stripebench run/reproduce
  --no-render-ahead``. A helper that cannot start is reported in one line and
  the run goes on without it.
"""

from __future__ import annotations

import contextlib
import io
import logging
import os
import threading
import time
import uuid
from typing import Any, Callable, Sequence

__all__ = ["RenderAhead", "reason_off", "usable_cores", "HELPER_THREADS", "MARGIN", "NICE", "MIN_PIXEL_SAMPLES",
           "GRACE_S"]

# the helper's drjit threads: 1 and 2 measured alike on the paper profile (272 and 274 s against 275 s of
# wall time); at nice 19 it rarely gets more than the one core the run leaves idle
HELPER_THREADS = 1
MARGIN = 0  # the helper renders a frame only when it lies more than MARGIN frames after the run's current one
NICE = 19  # the helper's scheduling priority: it gets a core only when the run (or anyone) leaves one idle
# the least uncached work (pixels x spp summed over the frames) worth a helper: its fixed cost in the run's
# process is about 1.5-2.5 s (measured on the ci and quick profiles, 8e6 and 4e6, where it made runs slower);
# one paper frame (512x480, 16 spp) is 3.9e6
MIN_PIXEL_SAMPLES = 4e7
GRACE_S = 2.0  # the longest the run waits for an answer from the helper's cluster when stopping it


def usable_cores() -> int:
    """The CPU cores this process may use (its affinity where the OS tells it, else ``os.cpu_count()``)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def reason_off(enabled: bool, scenes_: Sequence, *, cores: int | None = None) -> str | None:
    """Why render-ahead is off for a run, or None when it is on.

    Parameters
    ----------
    enabled : bool
        The configuration's ``render_ahead`` (False also from ``--no-render-ahead``).
    scenes_ : sequence of scenes.Scene
        One scene per experiment, as the run renders them.
    cores : int, optional
        Usable CPU cores (default :func:`usable_cores`).

    Returns
    -------
    str or None
        A short reason (``"turned off"``, ``"1 core"``, ``"one experiment"``,
        ``"render cache off"``), or None.

    Examples
    --------
    >>> reason_off(True, ["a scene"], cores=2)
    'one experiment'
    >>> reason_off(False, [], cores=2)
    'turned off'
    """
    cores = usable_cores() if cores is None else cores
    if not enabled:
        return "turned off"
    if cores < 2:
        return f"{cores} core"
    if len(scenes_) < 2:
        return "one experiment"
    if not all(s.params["cache"] for s in scenes_):
        return "render cache off"
    return None


def _lower_priority(nice: int) -> None:
    """Give every thread of this process the scheduling priority ``nice`` (Linux sets it per thread;
    elsewhere :func:`os.nice` sets the process's). Best effort: a refusal is ignored."""
    tasks = "/proc/self/task"
    if os.path.isdir(tasks):
        for tid in os.listdir(tasks):
            with contextlib.suppress(OSError, ValueError):
                os.setpriority(os.PRIO_PROCESS, int(tid), nice)
    else:
        with contextlib.suppress(OSError):
            os.nice(max(0, nice - os.nice(0)))


def _render_behind(scenes_: list, jobs: list[tuple[int, int, float]], spp: list[int], seed: int, position: str,
                   progress: str, threads: int, margin: int, nice: int) -> dict[str, Any]:
    """The helper's task (runs on the Dask worker): render ``jobs`` into the cache, in the order given.

    ``jobs`` are ``(flat index, experiment index, mirror angle in deg)``, descending
    flat index. Before each frame the ``position`` Variable (the run's frame) is
    read; the loop ends when the frame is at most ``margin`` frames ahead of it.

    Returns
    -------
    dict
        ``rendered``: ``(flat index, end time)`` of each frame rendered (``time.time()``, s);
        ``skipped``: frames found cached; ``pid``.
    """
    from dask.distributed import Variable

    pos, done = Variable(position), Variable(progress)
    rendered, skipped = [], 0
    _lower_priority(nice)
    devnull = os.open(os.devnull, os.O_WRONLY)  # this worker process's stderr (Mitsuba's, Dask's notes while it
    os.dup2(devnull, 2)                         # is killed): a helper's failure is reported through its future
    os.close(devnull)
    with contextlib.redirect_stderr(io.StringIO()):  # the variant note and cache notes: the run says its own
        from scenes import variant

        variant.mitsuba()
        import drjit

        drjit.set_thread_count(int(threads))
        _lower_priority(nice)  # drjit's own threads too
        current = None
        for j, k, angle in jobs:
            try:
                run_at = pos.get(timeout=10)
            except Exception:  # noqa: BLE001 - the run is gone or stopping: stop
                break
            if j <= run_at + margin:
                break
            if current is not None and current != k:
                scenes_[current] = None  # free the previous experiment's Mitsuba scenes
            current = k
            scene = scenes_[k]
            if scene.is_cached(angle, spp=spp[k], seed=seed):
                skipped += 1
                continue
            scene.render(angle, spp=spp[k], seed=seed)
            rendered.append((j, time.time()))
            done.set(rendered)
    return {"rendered": rendered, "skipped": skipped, "pid": os.getpid()}


class RenderAhead:
    """The render-ahead helper of one run (see the module docstring).

    Parameters
    ----------
    scenes_ : sequence of scenes.Scene
        The experiments' scenes, in run order.
    angles : sequence of array-like
        Each experiment's mirror angles (deg), in run order.
    seed : int
        The run's seed (every frame renders with it and its scene's ``spp``).
    pending : sequence of array-like of bool, optional
        Per experiment, (F,) which frames the run will render (default all; a
        resumed run's checkpoints hold the others: :func:`bench.run.scan.pending_frames`).
    threads : int
        drjit threads of the helper.
    nice : int
        The helper's scheduling priority, 0 (the run's) .. 19 (the lowest).
    say : callable
        Receives one-line notes (a helper that could not start).

    Use :meth:`start`, :meth:`at` before each frame the run renders, and
    :meth:`stop` (always: in a ``finally``), or the context manager, which
    starts and stops.
    """

    def __init__(self, scenes_: Sequence, angles: Sequence, seed: int, *, pending: Sequence | None = None,
                 threads: int = HELPER_THREADS, nice: int = NICE, say: Callable[[str], None] = lambda m: None):
        if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
            raise ValueError(f"`threads` must be an integer >= 1, got {threads!r}")
        if isinstance(nice, bool) or not isinstance(nice, int) or not 0 <= nice <= 19:
            raise ValueError(f"`nice` must be an integer 0 .. 19, got {nice!r}")
        self.scenes = list(scenes_)
        self.angles = [[float(a) for a in exp_angles] for exp_angles in angles]
        if len(self.angles) != len(self.scenes):
            raise ValueError(f"`angles` must list one scan per scene ({len(self.scenes)}), got {len(self.angles)}")
        self.seed = int(seed)
        self.pending = ([[True] * len(a) for a in self.angles] if pending is None
                        else [[bool(p) for p in exp_pending] for exp_pending in pending])
        if [len(p) for p in self.pending] != [len(a) for a in self.angles]:
            raise ValueError("`pending` must hold one flag per frame of `angles`")
        self.threads, self.nice = threads, nice
        self._say = say
        self.offsets = [sum(len(a) for a in self.angles[:k]) for k in range(len(self.angles))]
        self.n_frames = sum(len(a) for a in self.angles)
        self._cluster = self._client = self._future = self._pos = self._done = self._starting = None
        self._run_at = -1  # the frame the run is rendering (flat index)
        self._error = ""
        self._started_at: dict[int, float] = {}  # flat index -> when the run started rendering it
        self._level = None
        self.result: dict[str, Any] | None = None

    # -- the run's side ------------------------------------------------------------------------------------------
    def start(self) -> bool:
        """Start the helper when enough is left to render; True when it runs.

        Not started (False) when every frame is cached or done, or the uncached
        frames hold fewer than :data:`MIN_PIXEL_SAMPLES` pixel-samples (a short run
        would lose more to the helper's fixed cost than it gains).

        The cluster starts in a thread, so this returns at once. A helper that
        cannot start (Dask missing, no worker) never raises: :meth:`stop` says so
        in one line and the run renders every frame itself.
        """
        jobs = [(self.offsets[k] + i, k, a) for k in range(len(self.scenes)) for i, a in enumerate(self.angles[k])
                if self.pending[k][i] and not self.scenes[k].is_cached(a, spp=self.scenes[k].params["spp"],
                                                                      seed=self.seed)]
        work = sum(self.scenes[k].params["width"] * self.scenes[k].params["height"]
                   * sum(self.scenes[k].sample_counts()[1]) for _, k, _ in jobs)
        if not jobs or work < MIN_PIXEL_SAMPLES:
            self.result = {"frames": self.n_frames, "rendered": 0, "used": 0, "started": False,
                           "why": "cached" if not jobs else f"little to render ({len(jobs)} frames, {work:.2g} "
                                                            f"pixel-samples < {MIN_PIXEL_SAMPLES:.2g})"}
            return False
        jobs.reverse()
        from scenes import cache as _cache, variant as _variant

        env = {_variant.ENV_VARIANT: _variant.choose(), _cache.ENV_CACHE_DIR: str(_cache.cache_root())}
        if os.environ.get(_variant.ENV_LLVM_TARGET):  # the LLVM target this process renders for
            env[_variant.ENV_LLVM_TARGET] = os.environ[_variant.ENV_LLVM_TARGET]
        dist = logging.getLogger("distributed")
        self._level = dist.level
        dist.setLevel(logging.ERROR)  # the nanny's notes when it kills a busy worker
        # the cluster starts in a thread (about a second): the run begins its first frame meanwhile
        self._starting = threading.Thread(target=self._start_cluster, args=(jobs, env), daemon=True,
                                          name="stripebench-renderahead-start")
        self._starting.start()
        return True

    def _start_cluster(self, jobs, env) -> None:
        try:
            from dask.distributed import Client, Variable

            from bench.run.cluster import local_cluster

            self._cluster = local_cluster(1, env)
            self._client = Client(self._cluster)
            name = f"stripebench-renderahead-{uuid.uuid4().hex}"
            pos, self._done = Variable(name, self._client), Variable(f"{name}-done", self._client)
            pos.set(self._run_at)
            self._done.set([])
            self._future = self._client.submit(
                _render_behind, self.scenes, jobs, [s.params["spp"] for s in self.scenes], self.seed, name,
                f"{name}-done", self.threads, MARGIN, self.nice, pure=False, key=f"{name}-task")
            self._pos = pos
            pos.set(self._run_at)  # the run may have moved on while the task was submitted
        except Exception as exc:  # noqa: BLE001 - an optimisation: the run goes on without it
            self._error = f"did not start ({type(exc).__name__}: {exc})"

    def wait(self, n_frames: int, timeout_s: float) -> int:
        """Block until the helper has rendered ``n_frames`` frames, finished, or ``timeout_s`` passed
        (for tests and measurements); returns how many it has rendered."""
        t_end = time.monotonic() + timeout_s
        if self._starting is not None:
            self._starting.join(timeout_s)
        n = 0
        while self._future is not None and time.monotonic() < t_end:
            with contextlib.suppress(Exception):
                n = len(self._done.get(timeout=1))
            if n >= n_frames or self._future.done():
                break
            time.sleep(0.1)
        return n

    def at(self, experiment: int, frame: int) -> None:
        """The run is about to render frame ``frame`` of experiment ``experiment`` (both 0-based)."""
        j = self.offsets[experiment] + frame
        self._started_at.setdefault(j, time.time())
        self._run_at = j
        pos = self._pos
        if pos is not None:
            pos.set(j)

    def stop(self) -> dict[str, Any]:
        """Stop the helper (without waiting for its current frame) and count its frames.

        Returns
        -------
        dict
            ``frames`` (the run's), ``rendered`` (by the helper), ``used`` (of those, the
            frames the helper finished before the run reached them: the run's cache hits),
            ``started``, ``threads``, ``nice``, ``stop_s`` (how long stopping took, s), ``error``
            (the helper's failure, "" if none).
        """
        if self.result is not None:
            return self.result
        t0 = time.perf_counter()
        rendered: list = []
        self._run_at = self.n_frames
        if self._starting is not None:
            self._starting.join()  # a run shorter than the cluster's start (a second or two) waits for it
        error = self._error
        if error:
            self._say(f"stripebench: render-ahead helper {error}; every frame was rendered in this process")
        try:
            if self._pos is not None:
                self._pos.set(self.n_frames)  # past the end: the helper stops before its next frame
            if self._future is not None:
                if self._future.status == "error":
                    exc = self._future.exception(timeout=GRACE_S)
                    error = f"{type(exc).__name__}: {exc}"
                if self._future.status == "finished":  # it met the run earlier: its own count
                    rendered = self._future.result(timeout=GRACE_S)["rendered"]
                else:  # busy (a frame the run no longer needs) or failed: what it reported; killed below
                    with contextlib.suppress(Exception):
                        rendered = self._done.get(timeout=GRACE_S)
        finally:
            self._close()
        used = sum(1 for j, end in rendered if end <= self._started_at.get(j, float("inf")))
        self.result = {"frames": self.n_frames, "rendered": len(rendered), "used": used, "started": True,
                       "threads": self.threads, "nice": self.nice, "stop_s": time.perf_counter() - t0, "error": error}
        return self.result

    def summary_line(self) -> str:
        """One line for the end of a run, e.g. ``render-ahead: 57 of 200 frames rendered by the helper``."""
        r = self.stop()
        if not r["started"]:
            if r["why"] == "cached":
                return f"render-ahead: not needed, every one of the {r['frames']} frames was cached or done"
            return f"render-ahead: not started, {r['why']}"
        if r["error"]:
            return f"render-ahead: the helper failed ({r['error']}); {r['used']} of {r['frames']} frames rendered by it"
        extra = r["rendered"] - r["used"]
        more = f" ({extra} more also by the run)" if extra else ""
        return f"render-ahead: {r['used']} of {r['frames']} frames rendered by the helper{more}"

    def _close(self) -> None:
        cluster, client = self._cluster, self._client
        self._cluster = self._client = self._future = self._pos = self._done = None
        try:
            if cluster is not None:
                for nanny in list(cluster.workers.values()):  # kill a busy worker now, not after its render
                    with contextlib.suppress(Exception):
                        cluster.sync(nanny.kill, timeout=0.2)
            if client is not None:
                with contextlib.suppress(Exception):
                    client.close(timeout=2)
            if cluster is not None:
                with contextlib.suppress(Exception):
                    cluster.close(timeout=5)
        finally:
            if self._level is not None:
                logging.getLogger("distributed").setLevel(self._level)
                self._level = None

    def __enter__(self) -> "RenderAhead":
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop()
