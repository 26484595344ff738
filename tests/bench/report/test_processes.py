"""No process outlives the command that started it (issue 37, item 2): the report's figure workers die
with it, whatever signal ends it."""

import os
import signal
import subprocess
import sys
import time

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

# a process that draws two "figures" (30 s sleeps) in worker processes, as a report does
CHILD = ("import time, sys; from bench.report.runfigures import _draw; "
         "_draw([(time.sleep, (30,), {}), (time.sleep, (30,), {})], 2, lambda: print('drawing', flush=True))")


def _session(sid: int) -> list[str]:
    out = subprocess.run(["ps", "-s", str(sid), "-o", "pid=,cmd="], capture_output=True, text=True)
    return [line for line in out.stdout.splitlines() if line.strip()]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="process sessions and PDEATHSIG are Linux's")
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_figure_workers_die_with_the_report(sig):
    proc = subprocess.Popen([sys.executable, "-c", CHILD], cwd=REPO, stdout=subprocess.PIPE, text=True,
                            start_new_session=True, env={**os.environ, "PYTHONPATH": REPO})
    try:
        assert proc.stdout.readline().strip() == "drawing"
        deadline = time.monotonic() + 60
        while len(_session(proc.pid)) < 4 and time.monotonic() < deadline:  # itself, 2 workers, resource tracker
            time.sleep(0.2)
        assert len(_session(proc.pid)) >= 3, _session(proc.pid)
        os.kill(proc.pid, sig)
        proc.wait(10)
        deadline = time.monotonic() + 10
        while _session(proc.pid) and time.monotonic() < deadline:
            time.sleep(0.2)
        assert _session(proc.pid) == [], f"left behind after {sig.name}: {_session(proc.pid)}"
    finally:
        subprocess.run(["pkill", "-KILL", "-s", str(proc.pid)], capture_output=True)
        proc.stdout.close()
        proc.wait()
