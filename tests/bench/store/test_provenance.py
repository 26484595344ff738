"""bench.store.provenance: what made a result."""

import sys
import types

from bench.store import provenance as pv


def test_versions_name_python_and_every_package_that_shapes_results():
    v = pv.versions()
    assert v["python"].count(".") == 2
    assert {"numpy", "numba", "mitsuba", "drjit"} <= set(v)
    assert all(isinstance(x, str) and x for x in v.values())


def test_git_revision_is_this_checkout():
    rev = pv.git_revision()
    assert rev == "unknown" or len(rev.split("-")[0]) >= 12


def test_source_fingerprint_is_stable_and_the_code_fingerprint_follows_a_plugin(tmp_path, monkeypatch):
    import trackers

    a = pv.source_fingerprint()
    assert a == pv.source_fingerprint() and len(a) == 16
    assert pv.code_fingerprint() == pv.code_fingerprint([trackers.make("dp4")])  # the library is in `a` already
    # a plugin tracker from a module of its own: its file enters the fingerprint, and an edit changes it
    src = tmp_path / "myplugin.py"
    src.write_text("import trackers\nclass Mine(trackers.Tracker):\n    name = 'mine'\n"
                   "    def find_stripe(self, image, background):\n        return None\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import importlib

    mod = importlib.import_module("myplugin")
    try:
        files = pv.tracker_source_files([mod.Mine()])
        assert files == [src.resolve()]
        before = pv.code_fingerprint([mod.Mine()])
        src.write_text(src.read_text() + "# edited\n")
        assert pv.code_fingerprint([mod.Mine()]) != before
    finally:
        sys.modules.pop("myplugin", None)


def test_a_wrapped_tracker_is_traced_to_the_tracker_it_runs():
    inner = types.SimpleNamespace()
    wrapper = types.SimpleNamespace(wrapped=inner)
    assert pv.tracker_source_files([wrapper]) == pv.tracker_source_files([inner])
