"""Shared configuration: private caches and run folders for the test session."""

import os

import pytest

# numba's on-disk cache lives next to the sources unless a directory is chosen
os.environ.setdefault("NUMBA_CACHE_DIR", os.path.join(os.path.dirname(__file__), "..", ".cache", "numba"))


@pytest.fixture(scope="session", autouse=True)
def _private_render_cache_and_runs(tmp_path_factory):
    """Renders and runs of the tests go to temporary folders, never the user's."""
    saved = {k: os.environ.get(k) for k in ("STRIPEBENCH_CACHE_DIR", "STRIPEBENCH_RUNS")}
    os.environ["STRIPEBENCH_CACHE_DIR"] = str(tmp_path_factory.mktemp("stripebench-cache"))
    os.environ["STRIPEBENCH_RUNS"] = str(tmp_path_factory.mktemp("stripebench-runs"))
    yield
    for k, v in saved.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v


@pytest.fixture
def register_tracker():
    """``register(name, factory, *, replace=False)``: a tracker registered for one test through the
    public registry (``trackers.register``), removed after it; ``replace=True`` swaps a registered
    one and restores it afterwards."""
    import trackers

    undo = []

    def register(name, factory, *, replace=False):
        old = trackers.unregister(name) if replace else None
        trackers.register(name, factory)
        undo.append((name, old))
        return factory

    yield register
    for name, old in reversed(undo):
        trackers.unregister(name)
        if old is not None:
            trackers.register(name, old)


_JAX_CHILD = "STRIPEBENCH_TEST_JAX_CHILD"


@pytest.fixture
def jax_child(request):
    """Run a test that needs JAX in a child pytest process: JAX starts threads, and a process that has
    imported it warns on every later ``os.fork()`` (which the external tracker's and the figure
    workers' tests do), so JAX must never enter this test session's process.

    Use it as ``if not jax_child: return`` at the top of the test: in this process the fixture runs the
    same test in a child (``python -m pytest NODEID``), asserts that it passed and returns False; in the
    child it returns True and the body runs. Skips when JAX is not installed (the ``learn`` extra).
    """
    import importlib.util
    import subprocess
    import sys

    if importlib.util.find_spec("jax") is None:
        pytest.skip("JAX is not installed (pip install -e '.[learn]')")
    if os.environ.get(_JAX_CHILD) == request.node.nodeid:
        return True
    root = str(request.config.rootpath)
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", request.node.nodeid],
                          cwd=root, env={**os.environ, _JAX_CHILD: request.node.nodeid}, capture_output=True,
                          text=True, timeout=1800)
    assert proc.returncode == 0, f"the child run of {request.node.nodeid} failed:\n{proc.stdout[-6000:]}\n{proc.stderr[-2000:]}"
    assert " passed" in proc.stdout and " skipped" not in proc.stdout, proc.stdout[-2000:]
    return False


def pytest_sessionfinish(session, exitstatus):
    """Fail the session when JAX was imported into it (see :func:`jax_child`): a later fork would warn."""
    import sys

    if "jax" in sys.modules and _JAX_CHILD not in os.environ and exitstatus == 0:
        print("\nstripebench tests: JAX was imported into the test session's process; run such tests through "
              "the `jax_child` fixture (tests/conftest.py)", file=sys.stderr)
        session.exitstatus = 1
