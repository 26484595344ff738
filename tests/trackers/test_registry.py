import textwrap

import numpy as np
import pytest

import trackers
from trackers import Track, Tracker
from trackers._registry import Registry


def test_builtin_trackers_are_registered():
    names = trackers.available()
    assert names == sorted(names)
    assert {"threshold", "centroid", "dp4", "dp8"} <= set(names)


@pytest.mark.parametrize("name", ["threshold", "centroid", "dp4", "dp8"])
def test_make_returns_a_new_tracker_with_that_name(name):
    a = trackers.make(name)
    b = trackers.make(name)
    assert isinstance(a, Tracker) and a.name == name and a is not b


def test_make_passes_parameters():
    t = trackers.make("dp8", eps=2.5)
    assert t.get_params()["eps"] == 2.5


def test_unknown_name_lists_the_available():
    with pytest.raises(KeyError, match=r"unknown tracker 'nope'; available: .*centroid.*dp4.*dp8.*threshold"):
        trackers.make("nope")


def test_registering_a_name_twice_is_an_error():
    reg = Registry(group="stripebench.tests.none")
    reg.register("a", lambda: None)
    with pytest.raises(ValueError, match="a tracker named 'a' is already registered"):
        reg.register("a", lambda: None)
    with pytest.raises(ValueError, match="already registered"):
        trackers.register("dp4", "trackers.dp:DP4Tracker")


def test_register_as_decorator_and_bad_names():
    reg = Registry(group="stripebench.tests.none")

    @reg.register("mine")
    class Mine(Tracker):
        name = "mine"

        def _track(self, image, background):
            return Track.empty(image.shape[0])

    assert reg.available() == ["mine"]
    assert isinstance(reg.make("mine"), Mine)
    with pytest.raises(ValueError, match="`name` must be a non-empty string, got ''"):
        reg.register("", Mine)


def test_factory_must_return_a_tracker():
    reg = Registry(group="stripebench.tests.none")
    reg.register("odd", lambda: 42)
    with pytest.raises(TypeError, match="factory of tracker 'odd' returned int"):
        reg.make("odd")


def _write_plugin(tmp_path, group):
    (tmp_path / "sb_plugin_mod.py").write_text(
        textwrap.dedent(
            """
            import numpy as np
            from trackers import Track, Tracker

            class Plug(Tracker):
                name = "plug"
                def _track(self, image, background):
                    return Track(np.zeros(image.shape[0]), np.ones(image.shape[0]))

            class Misnamed(Plug):
                name = "something-else"
            """
        )
    )
    dist = tmp_path / "sb_plugin-0.1.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: sb-plugin\nVersion: 0.1\n")
    (dist / "entry_points.txt").write_text(
        f"[{group}]\n"
        "plug = sb_plugin_mod:Plug\n"
        "broken = sb_plugin_missing_module:Thing\n"
        "notatracker = sb_plugin_mod:np\n"
        "misnamed = sb_plugin_mod:Misnamed\n"
        "threshold = sb_plugin_mod:Plug\n"
    )


def test_entry_points_are_loaded_lazily_and_broken_ones_warn(tmp_path, monkeypatch):
    group = "stripebench.trackers"
    _write_plugin(tmp_path, group)
    monkeypatch.syspath_prepend(str(tmp_path))
    reg = Registry(group)
    reg.register("threshold", "trackers.threshold:ThresholdTracker")
    with pytest.warns(RuntimeWarning) as record:
        names = reg.available()
    messages = "\n".join(str(w.message) for w in record)
    assert "could not load tracker entry point 'broken' (sb_plugin_missing_module:Thing)" in messages
    assert "'notatracker'" in messages and "not a Tracker subclass" in messages
    assert "'misnamed'" in messages and "declares name='something-else'" in messages
    assert "'threshold'" in messages and "already registered" in messages
    assert names == ["plug", "threshold"]
    t = reg.make("plug")
    assert t.name == "plug" and t.track(np.ones((3, 3))).columns.tolist() == [0.0, 0.0, 0.0]
    # loaded once: no second round of warnings
    assert reg.available() == ["plug", "threshold"]


def test_unregister_returns_the_factory_and_refuses_an_unknown_name():
    import trackers as T

    T.register("sb-temporary", T.make("dp4").__class__)
    assert T.unregister("sb-temporary") is T.make("dp4").__class__
    assert "sb-temporary" not in T.available()
    with pytest.raises(KeyError, match="no tracker named 'sb-temporary'"):
        T.unregister("sb-temporary")
