"""One tracker on one frame, for every caller: scans, sweeps, ``stripebench track`` and ``stripebench real``.

:func:`track_frame` is the unit of work. It never raises for anything the
tracker does: a failure is data (:class:`TrackResult` with a status code from
:data:`STATUS` and a one-line message), and the run goes on. It also keeps
trackers apart from each other:

- the tracker gets **read-only views** of the frame and background, so a
  plugin that writes into its input fails (status ``raised``) instead of
  changing what the trackers after it see;
- what the tracker prints goes to stderr, never to stdout (where commands
  write their results);
- columns outside the image (``col < -0.5`` or ``col > W - 0.5``) fail the frame
  (``out-of-image``), wrong shapes or types fail it (``bad-output``);
- ``sys.exit`` inside a tracker fails the frame (``raised``), it does not end the run;
- a tracker setting may carry ``timeout_s`` (per frame) and ``isolate = true``:
  :class:`IsolatedTracker` runs the tracker in its own worker process, so a hang
  (``timeout``), a segfault or an ``os._exit`` (``crashed``) fails that frame
  and the next frame gets a fresh worker. Without ``isolate`` a timeout is
  enforced in the process with ``SIGALRM`` (main thread only); it interrupts
  Python code, not a native loop that never returns to the interpreter.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
import time
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.store.checkpoint import STATUS

__all__ = ["STATUS", "TrackResult", "track_frame", "build_trackers", "TimedTracker", "IsolatedTracker",
           "TrackerTimeout", "TrackerCrashed", "TrackerRaised"]



class TrackerTimeout(Exception):
    """A tracker took longer than its ``timeout_s`` on one frame."""


class TrackerCrashed(Exception):
    """A tracker's worker process died (segfault, ``os._exit``) on one frame."""


class TrackerRaised(Exception):
    """A tracker raised in its worker process; the message is the worker's one line."""


@dataclass(frozen=True)
class TrackResult:
    """One tracker on one frame.

    Attributes
    ----------
    columns, score : numpy.ndarray, shape (H,), float64
        NaN everywhere when the frame failed.
    seconds : float
        Wall time of the call.
    status : int
        A key of :data:`STATUS` (0 = ok).
    message : str
        One line: why the frame failed ("" when ok).
    """

    columns: np.ndarray
    score: np.ndarray
    seconds: float
    status: int
    message: str

    @property
    def ok(self) -> bool:
        return self.status == 0


def _read_only(a):
    if a is None:
        return None
    if isinstance(a, np.ndarray):
        v = a.view()
        v.flags.writeable = False
        return v
    return a


@contextlib.contextmanager
def _alarm(timeout_s: float | None):
    """Raise :class:`TrackerTimeout` in this thread after ``timeout_s`` seconds (main thread, Unix only)."""
    usable = (timeout_s is not None and hasattr(signal, "setitimer")
              and threading.current_thread() is threading.main_thread())
    if not usable:
        yield
        return

    def fire(signum, frame):
        raise TrackerTimeout(f"took longer than timeout_s = {timeout_s:g} s")

    old = signal.signal(signal.SIGALRM, fire)
    signal.setitimer(signal.ITIMER_REAL, float(timeout_s))
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)


def _where(exc: BaseException) -> str:
    tb = traceback.extract_tb(exc.__traceback__)
    return f" ({Path(tb[-1].filename).name}:{tb[-1].lineno})" if tb else ""


def track_frame(tracker, image, background, colour=None) -> TrackResult:
    """Run ``tracker`` on one frame and check what it returns (never raises but for Ctrl-C).

    Parameters
    ----------
    tracker : trackers.Tracker, TimedTracker or IsolatedTracker
        Anything with ``track(image, background=...) -> trackers.Track``
        (:func:`build_trackers` makes them from tracker settings).
    image : numpy.ndarray, shape (H, W)
        The frame (uint8 DN or float); the tracker sees a read-only view.
    background : numpy.ndarray, shape (H, W), or None
        The laser-off frame; read-only too.
    colour : numpy.ndarray, shape (H, W), or None
        The laser colour's evidence of a colour frame (:func:`bench.run.camera_view.colour_of`); passed only
        where given, so a tracker whose ``track`` takes two arguments still runs on grey frames.

    Returns
    -------
    TrackResult

    Examples
    --------
    >>> import trackers
    >>> img = np.zeros((4, 6)); img[:, 2] = 100.0
    >>> r = track_frame(trackers.make("threshold"), img, None)
    >>> STATUS[r.status], r.columns.tolist()
    ('ok', [2.0, 2.0, 2.0, 2.0])
    """
    import trackers

    H, W = image.shape
    nan = np.full(H, np.nan)
    t0 = time.perf_counter()
    try:
        with contextlib.redirect_stdout(sys.stderr):
            extra = {} if colour is None else {"colour": _read_only(colour)}
            out = tracker.track(_read_only(image), background=_read_only(background), **extra)
    except KeyboardInterrupt:
        raise
    except TrackerTimeout as exc:
        return TrackResult(nan, nan, time.perf_counter() - t0, 4, str(exc))
    except TrackerCrashed as exc:
        return TrackResult(nan, nan, time.perf_counter() - t0, 5, str(exc))
    except TrackerRaised as exc:
        return TrackResult(nan, nan, time.perf_counter() - t0, 1, str(exc))
    except SystemExit as exc:  # a tracker's sys.exit fails its frame, not the run
        return TrackResult(nan, nan, time.perf_counter() - t0, 1, f"called sys.exit({exc.code!r}){_where(exc)}")
    except Exception as exc:  # a tracker's failure is data, not a crash
        msg = f"{type(exc).__name__}: {exc}".splitlines()[0] if str(exc) else type(exc).__name__
        return TrackResult(nan, nan, time.perf_counter() - t0, 1, msg + _where(exc))
    dt = time.perf_counter() - t0
    if not isinstance(out, trackers.Track):
        return TrackResult(nan, nan, dt, 2, f"returned {type(out).__name__}, not Track")
    if out.columns.shape != (H,):
        return TrackResult(nan, nan, dt, 2, f"returned {out.columns.shape[0]} rows for a frame of {H}")
    cols = out.columns
    bad = ~np.isnan(cols) & ((cols < -0.5) | (cols > W - 0.5))
    if bad.any():
        return TrackResult(nan, nan, dt, 3, f"{int(bad.sum())} column(s) outside the image, e.g. {cols[bad][0]!r}")
    return TrackResult(np.array(cols), np.array(out.score), dt, 0, "")


# ---------------------------------------------------------------------------------------------------- settings


class TimedTracker:
    """A tracker with a per-frame time limit, run in this process (``timeout_s`` without ``isolate``).

    The limit is enforced with ``SIGALRM`` in the main thread (elsewhere it is
    not enforced): it interrupts Python code, not a native loop that does not
    return to the interpreter; use ``isolate = true`` for those. ``repr`` is the
    tracker's own.
    """

    def __init__(self, tracker, timeout_s: float):
        if not (isinstance(timeout_s, (int, float)) and 0 < timeout_s < float("inf")):
            raise ValueError(f"`timeout_s` must be a finite number of seconds > 0, got {timeout_s!r}")
        self.wrapped = tracker
        self.timeout_s = float(timeout_s)

    def __repr__(self) -> str:
        return repr(self.wrapped)

    def __getattr__(self, attr):
        if attr.startswith("_") or attr == "wrapped":
            raise AttributeError(attr)
        return getattr(self.wrapped, attr)

    def track(self, image, *, background=None, **colour):
        with _alarm(self.timeout_s):
            return self.wrapped.track(image, background=background, **colour)


def build_trackers(specs) -> dict:
    """label -> the runnable tracker of each setting: the tracker itself, or wrapped in
    :class:`TimedTracker` (``timeout_s``) or :class:`IsolatedTracker` (``isolate``).

    Parameters
    ----------
    specs : iterable of bench.config.TrackerSpec

    Examples
    --------
    >>> from bench.config import parse_trackers
    >>> built = build_trackers(parse_trackers(["dp4", {"name": "centroid", "timeout_s": 2.0}]))
    >>> {label: type(t).__name__ for label, t in built.items()}
    {'dp4': 'DP4Tracker', 'centroid': 'TimedTracker'}
    """
    out = {}
    for s in specs:
        t = s.make()
        if getattr(s, "isolate", False):
            t = IsolatedTracker(t, getattr(s, "timeout_s", None))
        elif getattr(s, "timeout_s", None) is not None:
            t = TimedTracker(t, s.timeout_s)
        out[s.label] = t
    return out


# ---------------------------------------------------------------------------------------------------- isolation

_START_S = 120.0  # a worker imports numpy, numba and the tracker's package


def _worker(conn, module: str, qualname: str, params: dict) -> None:  # pragma: no cover - the child process
    """The child's loop: build the tracker once (its class by import path), then answer one frame per message."""
    import importlib

    import trackers
    from trackers.processes import die_with_parent

    die_with_parent()  # a worker never outlives the run that started it

    try:
        cls = importlib.import_module(module)
        for part in qualname.split("."):
            cls = getattr(cls, part)
        tracker = cls(**params)
    except Exception as exc:
        conn.send(("raised", f"{type(exc).__name__}: {exc}".splitlines()[0]))
        return
    conn.send(("ready", ""))
    while True:
        try:
            msg = conn.recv()
        except EOFError:
            return
        if msg is None:
            return
        image, background, colour = msg
        try:
            with contextlib.redirect_stdout(sys.stderr):
                extra = {} if colour is None else {"colour": _read_only(colour)}
                out = tracker.track(_read_only(image), background=_read_only(background), **extra)
            if isinstance(out, trackers.Track):
                conn.send(("ok", (np.asarray(out.columns), np.asarray(out.score))))
            else:
                conn.send(("bad", type(out).__name__))
        except SystemExit as exc:
            conn.send(("raised", f"called sys.exit({exc.code!r}){_where(exc)}"))
        except BaseException as exc:  # noqa: BLE001 - everything the tracker does is reported to the parent
            text = f"{type(exc).__name__}: {exc}".splitlines()[0] if str(exc) else type(exc).__name__
            conn.send(("raised", text + _where(exc)))


class IsolatedTracker:
    """A tracker run in its own worker process, with a per-frame time limit.

    Parameters
    ----------
    tracker : trackers.Tracker
        The tracker to run; the worker builds another of its class (imported by
        its module path, so it must be importable, not defined in ``__main__``)
        with the same ``get_params()``.
    timeout_s : float, optional
        Seconds one frame may take (the worker's start is not counted); the
        worker is killed when it is exceeded. None: no limit.

    A frame whose worker hangs or dies raises :class:`TrackerTimeout` or
    :class:`TrackerCrashed` (which :func:`track_frame` records); the next frame
    starts a new worker. ``repr`` is the tracker's own, so results and their
    fingerprints do not depend on how the tracker was run. Call :meth:`close`
    (or use it as a context manager) to stop the worker.
    """

    def __init__(self, tracker, timeout_s: float | None = None):
        cls = type(tracker)
        if cls.__module__ == "__main__" or "<locals>" in cls.__qualname__:
            raise ValueError(f"`tracker` must be of an importable class to run isolated, got {cls.__qualname__} "
                             f"from {cls.__module__}")
        if timeout_s is not None and not (isinstance(timeout_s, (int, float)) and 0 < timeout_s < float("inf")):
            raise ValueError(f"`timeout_s` must be a finite number of seconds > 0, got {timeout_s!r}")
        self.wrapped = tracker
        self.timeout_s = timeout_s
        self._target = (cls.__module__, cls.__qualname__, tracker.get_params())
        self._proc = None
        self._conn = None

    def __repr__(self) -> str:
        return repr(self.wrapped)

    def __getattr__(self, attr):  # subpixel, uses_background, ... of the tracker itself
        if attr.startswith("_") or attr == "wrapped":
            raise AttributeError(attr)
        return getattr(self.wrapped, attr)

    def _start(self) -> None:
        import multiprocessing as mp

        ctx = mp.get_context("spawn")  # never fork a process that holds JIT threads
        parent, child = ctx.Pipe()
        self._proc = ctx.Process(target=_worker, args=(child, *self._target), daemon=True)
        self._proc.start()
        child.close()
        self._conn = parent
        if not self._conn.poll(_START_S):
            self._kill()
            raise TrackerTimeout(f"its worker did not start within {_START_S:g} s")
        kind, text = self._conn.recv()
        if kind != "ready":
            self.close()
            raise TrackerRaised(f"could not start {self._target[1]} in a worker: {text}")

    def _died(self) -> str:
        self._proc.join(1.0)
        code = self._proc.exitcode
        if code is not None and code < 0:
            try:
                sig = signal.Signals(-code).name
            except ValueError:
                sig = f"signal {-code}"
            return f"the worker died ({sig})"
        return f"the worker exited with status {code}"

    def track(self, image, *, background=None, colour=None):
        """Track one frame in the worker (see :meth:`trackers.Tracker.track`)."""
        from trackers import Track

        def arr(a):
            return None if a is None else np.ascontiguousarray(a)

        try:
            if self._proc is None or not self._proc.is_alive():
                self._start()
            self._conn.send((arr(image), arr(background), arr(colour)))
            if not self._conn.poll(self.timeout_s):
                self._kill()
                raise TrackerTimeout(f"took longer than timeout_s = {self.timeout_s:g} s (worker killed)")
            kind, payload = self._conn.recv()
        except (EOFError, BrokenPipeError, ConnectionResetError):
            why = self._died()
            self._kill()
            raise TrackerCrashed(why) from None
        if kind == "ok":
            return Track(*payload)
        if kind == "bad":
            return type(payload, (), {})()  # not a Track: track_frame reports bad-output with the type's name
        raise TrackerRaised(payload)

    def _kill(self) -> None:
        if self._proc is not None:
            if self._proc.is_alive():
                self._proc.kill()
            self._proc.join(5.0)
        if self._conn is not None:
            self._conn.close()
        self._proc = self._conn = None

    def close(self) -> None:
        """Stop the worker (a new one starts on the next frame)."""
        if self._conn is not None and self._proc is not None and self._proc.is_alive():
            with contextlib.suppress(OSError):
                self._conn.send(None)
        self._kill()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        with contextlib.suppress(Exception):
            self.close()
