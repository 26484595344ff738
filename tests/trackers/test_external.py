"""trackers.external: another program as a tracker; the examples of docs/plugins.md compiled and run."""

import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import trackers
from trackers.external import ExternalTracker, parse_answer, png_bytes

DOC = Path(__file__).resolve().parents[2] / "docs" / "plugins.md"


def _example(name: str) -> str:
    m = re.search(rf"<!-- example: {re.escape(name)} -->\n```\w+\n(.*?)```", DOC.read_text(), re.S)
    assert m, f"docs/plugins.md has no example {name}"
    return m.group(1)


def _frame(h=6, w=10):
    img = np.full((h, w), 5, np.uint8)
    for r in range(h):
        img[r, 3 + r % 4] = 200
    img[2] = 5  # a row with no stripe
    return img


def _expected(img):
    cols = np.argmax(img, axis=1).astype(float)
    cols[img.max(axis=1) <= 40] = np.nan
    return cols


@pytest.fixture(scope="module")
def c_program(tmp_path_factory):
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler (cc or gcc) on this machine")
    d = tmp_path_factory.mktemp("c")
    (d / "argmax.c").write_text(_example("argmax.c"))
    subprocess.run([cc, "-O2", "-o", str(d / "argmax"), str(d / "argmax.c")], check=True)
    return d / "argmax"


def test_external_is_registered_but_not_in_the_default_list():
    assert "external" not in trackers.available()
    assert "external" in trackers.available(unlisted=True)
    assert type(trackers.make("external", command=["x"])).__name__ == "ExternalTracker"


def test_the_c_program_of_the_docs(c_program):
    t = trackers.make("external", command=[str(c_program), "{image}", "{out}"], image_format="pgm")
    img = _frame()
    tr = t.track(img)
    np.testing.assert_array_equal(tr.columns, _expected(img))
    assert tr.score[0] == 200.0
    t.close()


def test_the_persistent_python_script_of_the_docs(tmp_path):
    (tmp_path / "srv.py").write_text(_example("centroid_server.py"))
    t = ExternalTracker([sys.executable, str(tmp_path / "srv.py")], mode="persistent", image_format="pgm")
    for k in range(3):  # one process answers every frame
        img = np.roll(_frame(), k, axis=1)
        np.testing.assert_allclose(t.track(img, background=np.zeros_like(img)).columns, _expected(img))
    pid = t._proc.pid
    t.track(_frame())
    assert t._proc.pid == pid
    t.close()


def test_png_and_npy_inputs_reach_the_program_losslessly(tmp_path):
    import imageio.v3 as iio

    img = np.random.default_rng(0).integers(0, 256, (5, 7), dtype=np.uint8)
    np.testing.assert_array_equal(iio.imread(png_bytes(img), extension=".png"), img)
    script = ("import sys, numpy as np, shutil; shutil.copy(sys.argv[1], sys.argv[3]); "
              "open(sys.argv[2], 'w').write('0,1\\n')")
    keep = tmp_path / "seen.npy"
    t = ExternalTracker([sys.executable, "-c", script, "{image}", "{out}", str(keep)])
    f = np.random.default_rng(1).random((3, 4))
    assert t.track(f).columns.tolist()[0] == 1.0
    np.testing.assert_array_equal(np.load(keep), f)
    t.close()


@pytest.mark.parametrize("code, match", [
    ("import sys; sys.exit(3)", "exited with status 3"),
    ("pass", "wrote no answer"),
    ("open(r'{out}', 'w').write('0,abc\\n')", "not row,col"),
    ("open(r'{out}', 'w').write('9,1\\n')", "row 9 outside"),
    ("open(r'{out}', 'w').write('0,1\\n0,2\\n')", "given twice"),
    ("import time; time.sleep(10)", "timeout_s"),
])
def test_failures_fail_the_frame_through_track_frame(code, match):
    from bench.run.track import STATUS, track_frame

    t = ExternalTracker([sys.executable, "-c", code], timeout_s=1.0)
    r = track_frame(t, _frame(), None)
    assert STATUS[r.status] == "raised" and match in r.message and np.isnan(r.columns).all()
    t.close()


def test_a_hung_persistent_program_is_killed_and_restarted(tmp_path):
    from bench.run.track import STATUS, track_frame

    mark = tmp_path / "started-once"
    (tmp_path / "s.py").write_text(
        "import os, sys, time\n"
        f"hang = not os.path.exists({str(mark)!r}); open({str(mark)!r}, 'w').close()\n"
        "for line in sys.stdin:\n"
        "    time.sleep(30) if hang else None\n"
        "    print('0,1'); print('end', flush=True)\n")
    t = ExternalTracker([sys.executable, str(tmp_path / "s.py")], mode="persistent", timeout_s=1.0)
    first = track_frame(t, _frame(), None)
    assert STATUS[first.status] == "raised" and "timeout_s = 1 s (killed)" in first.message
    second = track_frame(t, _frame(), None)  # a fresh process, which answers
    assert second.ok and second.columns[0] == 1.0 and np.isnan(second.columns[1:]).all()
    t.close()


@pytest.mark.parametrize("params, match", [
    ({}, "`command` must be a non-empty list"),
    ({"command": ["x"], "mode": "daemon"}, "`mode`"),
    ({"command": ["x"], "image_format": "jpg"}, "`image_format`"),
    ({"command": ["x"], "timeout_s": 0}, "`timeout_s`"),
    ({"command": ["x", "{image}"], "mode": "persistent"}, "no placeholders"),
])
def test_bad_params_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        ExternalTracker(**params).track(_frame())


def test_parse_answer_ignores_a_header_and_empty_cols():
    tr = parse_answer("row,col,score\n0,1.5,2\n1,,\n", 3)
    assert tr.columns[0] == 1.5 and tr.score[0] == 2.0 and np.isnan(tr.columns[1:]).all()


def test_the_parameter_table_holds_for_the_external_tracker():
    import sys

    from trackers.testing import check_parameter_constraints

    t = ExternalTracker([sys.executable, "-c", "open(r'{out}', 'w').write('0,2\\n')"])
    check_parameter_constraints(t)
    t.close()


@pytest.mark.skipif(shutil.which("bash") is None or not sys.platform.startswith("linux"), reason="needs bash, Linux")
@pytest.mark.parametrize("mode", ["per-frame", "persistent"])
def test_a_timeout_kills_every_process_the_program_started(tmp_path, mode):
    """Issue 37 item 2: `bash -c "sleep 41; true"` used to leave its `sleep` running (and `run` waited for it)."""
    import time

    marker = f"sleep 41.{mode}"  # a command line of our own, to find the grandchild by
    script = tmp_path / "s.sh"
    script.write_text(f"#!/bin/bash\nexec -a '{marker}' sleep 41 &\nwait\n")
    script.chmod(0o755)
    t = ExternalTracker([str(script)], mode=mode, timeout_s=1.0)
    start = time.monotonic()
    with pytest.raises(TimeoutError, match="killed"):
        t.track(_frame())
    assert time.monotonic() - start < 20  # never waits for the grandchild
    t.close()
    time.sleep(0.5)
    left = subprocess.run(["pgrep", "-f", marker], capture_output=True, text=True).stdout.split()
    assert left == [], f"processes left: {left}"
