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
