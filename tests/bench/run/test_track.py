"""One tracker on one frame (bench.run.track): failures are data, trackers are kept apart."""

import textwrap

import numpy as np
import pytest

import trackers
from bench.config import ConfigError, parse_trackers
from bench.run.track import STATUS, IsolatedTracker, TimedTracker, build_trackers, track_frame
from trackers.testing import make_stripe_image

# Misbehaving trackers live in a module of their own so that a worker process can import them by name.
MISBEHAVING = textwrap.dedent('''
    import os, sys, time, ctypes
    import numpy as np
    from trackers import Track, Tracker

    class _Base(Tracker):
        def __init__(self, delay_s=0.0):
            self.delay_s = delay_s

    class Raises(_Base):
        name = "raises"
        def _track(self, image, background):
            raise RuntimeError("boom")

    class WrongShape(_Base):
        name = "wrong-shape"
        def _track(self, image, background):
            return Track.empty(image.shape[0] + 2)

    class Outside(_Base):
        name = "outside"
        def _track(self, image, background):
            return Track(np.full(image.shape[0], 1e4), np.ones(image.shape[0]))

    class Writes(_Base):
        name = "writes"
        def _track(self, image, background):
            image[:] = 0
            return Track.empty(image.shape[0])

    class Prints(_Base):
        name = "prints"
        def _track(self, image, background):
            print("hello from a plugin")
            return Track(np.zeros(image.shape[0]), np.ones(image.shape[0]))

    class Exits(_Base):
        name = "exits"
        def _track(self, image, background):
            sys.exit(3)

    class Sleeps(_Base):
        name = "sleeps"
        def _track(self, image, background):
            time.sleep(self.delay_s)
            return Track(np.zeros(image.shape[0]), np.ones(image.shape[0]))

    class Segfaults(_Base):
        name = "segfaults"
        def _track(self, image, background):
            ctypes.string_at(0)

    class HardExits(_Base):
        name = "hard-exits"
        def _track(self, image, background):
            os._exit(7)
''')


@pytest.fixture(scope="module")
def bad(tmp_path_factory):
    """The misbehaving trackers' module, importable here and in worker processes."""
    import importlib
    import sys

    root = tmp_path_factory.mktemp("plugins")
    (root / "sb_misbehaving.py").write_text(MISBEHAVING)
    sys.path.insert(0, str(root))
    try:
        yield importlib.import_module("sb_misbehaving")
    finally:
        sys.path.remove(str(root))
        sys.modules.pop("sb_misbehaving", None)


@pytest.fixture
def frame():
    img, _ = make_stripe_image(20, 30)
    return img


def test_track_frame_records_failures_instead_of_raising(bad, frame):
    ok = track_frame(trackers.make("centroid"), frame, None)
    assert STATUS[ok.status] == "ok" and ok.message == "" and not np.isnan(ok.columns).all()
    r = track_frame(bad.Raises(), frame, None)
    assert STATUS[r.status] == "raised" and "RuntimeError: boom" in r.message and np.isnan(r.columns).all()
    w = track_frame(bad.WrongShape(), frame, None)
    assert STATUS[w.status] == "raised" and "returned 22 rows for an image of 20" in w.message
    o = track_frame(bad.Outside(), frame, None)
    assert STATUS[o.status] == "out-of-image" and "outside the image" in o.message


def test_a_tracker_cannot_change_the_frame_the_next_one_sees(bad, frame):
    before = frame.copy()
    w = track_frame(bad.Writes(), frame, None)
    assert STATUS[w.status] == "raised" and "read-only" in w.message
    assert np.array_equal(frame, before)
    assert track_frame(trackers.make("centroid"), frame, None).ok


def test_what_a_tracker_prints_goes_to_stderr(bad, frame, capfd):
    assert track_frame(bad.Prints(), frame, None).ok
    out, err = capfd.readouterr()
    assert out == "" and "hello from a plugin" in err


def test_sys_exit_fails_the_frame_not_the_run(bad, frame):
    r = track_frame(bad.Exits(), frame, None)
    assert STATUS[r.status] == "raised" and r.message.startswith("called sys.exit(3)")


def test_a_timeout_in_the_process_fails_a_slow_frame(bad, frame):
    slow = track_frame(TimedTracker(bad.Sleeps(delay_s=5.0), 0.2), frame, None)
    assert STATUS[slow.status] == "timeout" and slow.seconds < 3.0
    assert track_frame(TimedTracker(bad.Sleeps(delay_s=0.0), 0.2), frame, None).ok


@pytest.mark.slow
def test_an_isolated_tracker_survives_hangs_segfaults_and_exits(bad, frame):
    with IsolatedTracker(bad.Sleeps(delay_s=0.0), timeout_s=30.0) as t:
        first = track_frame(t, frame, None)
        assert first.ok and repr(t) == repr(bad.Sleeps(delay_s=0.0))
    with IsolatedTracker(bad.Sleeps(delay_s=60.0), timeout_s=0.5) as t:
        r = track_frame(t, frame, None)
        assert STATUS[r.status] == "timeout" and "worker killed" in r.message
    for cls, why in ((bad.Segfaults, "SIGSEGV"), (bad.HardExits, "status 7")):
        with IsolatedTracker(cls(), timeout_s=60.0) as t:
            r = track_frame(t, frame, None)
            assert STATUS[r.status] == "crashed" and why in r.message, r.message
            again = track_frame(t, frame, None)  # a fresh worker for the next frame
            assert STATUS[again.status] == "crashed"
    with IsolatedTracker(trackers.make("centroid")) as t:
        iso = track_frame(t, frame, None)
    direct = track_frame(trackers.make("centroid"), frame, None)
    assert iso.ok and np.array_equal(iso.columns, direct.columns, equal_nan=True)
    with IsolatedTracker(bad.Raises()) as t:
        r = track_frame(t, frame, None)
        assert STATUS[r.status] == "raised" and "RuntimeError: boom" in r.message


def test_tracker_settings_carry_timeout_and_isolation():
    specs = parse_trackers(["dp4", {"name": "centroid", "timeout_s": 2, "isolate": True},
                            {"label": "t1", "name": "threshold", "timeout_s": 0.5}])
    assert specs[0].to_value() == "dp4"
    assert specs[1].to_value() == {"label": "centroid", "name": "centroid", "params": {}, "timeout_s": 2.0,
                                   "isolate": True}
    built = build_trackers(specs)
    assert isinstance(built["centroid"], IsolatedTracker) and isinstance(built["t1"], TimedTracker)
    assert repr(built["t1"]) == repr(trackers.make("threshold"))
    built["centroid"].close()
    for value, msg in (({"name": "dp4", "timeout_s": 0}, r"`trackers\[0\].timeout_s` must be a number of seconds"),
                       ({"name": "dp4", "timeout_s": float("nan")}, "timeout_s"),
                       ({"name": "dp4", "isolate": "yes"}, r"`trackers\[0\].isolate` must be true or false")):
        with pytest.raises(ConfigError, match=msg):
            parse_trackers([value])


def test_isolation_refuses_a_class_a_worker_cannot_import(frame):
    class Local(trackers.Tracker):
        name = "local"

        def _track(self, image, background):
            return trackers.Track.empty(image.shape[0])

    with pytest.raises(ValueError, match="importable class"):
        IsolatedTracker(Local())


def test_track_and_real_fail_out_of_image_columns_as_run_does(bad, frame):
    from bench.run.real import _track_all

    res = _track_all({"outside": bad.Outside(), "centroid": trackers.make("centroid")}, frame, None)
    tr, _, status, msg = res["outside"]
    assert status == "out-of-image" and "outside the image" in msg and not tr.detected.any()
    assert res["centroid"][2] == "ok" and res["centroid"][0].detected.any()
