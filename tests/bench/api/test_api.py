"""bench.api: evaluate one tracker on a profile, load a run; and docs/api.md's code blocks run."""

import pathlib
import re

import numpy as np
import pandas as pd
import pytest

import trackers
from bench import api
from bench.errors import ConfigError
from bench.store.files import RunFolderError

REPO = pathlib.Path(__file__).resolve().parents[3]
TINY = {"render": {"width": 64, "height": 60, "spp": 2, "ambient_spp": 1},
        "experiments": [{"scene": "cone", "material": "patchy", "n_angles": 3}],
        "n_samples": 12, "n_boot": 50, "render_ahead": False}


@pytest.fixture
def runs(tmp_path, monkeypatch):
    """An empty runs root for the test."""
    monkeypatch.setenv("STRIPEBENCH_RUNS", str(tmp_path / "runs"))
    return tmp_path / "runs"


class _Argmax(trackers.Tracker):
    """Not registered: the brightest pixel of every row."""

    name = "api_test_argmax"

    def __init__(self, offset_px: float = 0.0):
        self.offset_px = offset_px

    def find_stripe(self, image, background):
        return trackers.Track(np.argmax(image, axis=1) + float(self.offset_px), image.max(axis=1))


def test_evaluate_a_registered_name(runs):
    df = api.evaluate("dp4", **TINY)
    assert list(df["region"]) == ["all", "object"] and set(df["tracker"]) == {"dp4"}
    assert set(df["experiment"]) == {"cone-patchy"} and (df["frames"] == 3).all()
    run_dir = pathlib.Path(df.attrs["run_dir"])
    assert run_dir.parent == runs
    tables = api.load_run(run_dir)
    pd.testing.assert_frame_equal(tables.metrics, df, check_like=False)
    cfg = tables.summary["config"]
    assert cfg["trackers"] == ["dp4"] and cfg["baselines"] == [] and cfg["dp"] == []
    assert cfg["render"] == {"width": 64, "height": 60, "spp": 2, "ambient_spp": 1}
    assert "error_mm_dp4" in tables.samples.columns


def test_render_override_is_merged_over_the_profile(runs):
    df = api.evaluate("centroid", render={"width": 64, "height": 60}, experiments=TINY["experiments"],
                      n_boot=50, render_ahead=False)
    cfg = api.load_run(df.attrs["run_dir"]).summary["config"]
    assert cfg["render"]["spp"] == 8  # the quick profile's, kept
    assert (cfg["render"]["width"], cfg["render"]["height"]) == (64, 60)


def test_instance_parameters_are_recorded_and_used(runs):
    default = api.evaluate(trackers.make("centroid"), **TINY)
    strict = api.evaluate(trackers.make("centroid", k_sigma=1000.0), label="strict", **TINY)
    assert set(strict["tracker"]) == {"strict"}
    spec = api.load_run(strict.attrs["run_dir"]).summary["config"]["trackers"][0]
    assert spec["name"] == "centroid" and spec["params"]["k_sigma"] == 1000.0
    assert default.attrs["run_dir"] != strict.attrs["run_dir"]
    assert (default["coverage"] > 0.5).all() and (strict["coverage"] == 0.0).all()  # nothing stands 1000 sigma out


def test_an_unregistered_class_is_registered_for_the_call_only(runs):
    df = api.evaluate(_Argmax(), **TINY)
    assert set(df["tracker"]) == {"api_test_argmax"}
    assert "api_test_argmax" not in trackers.available(unlisted=True)
    shifted = api.evaluate(_Argmax(offset_px=5.0), label="shifted", **TINY)
    assert (shifted["px_mae"] > df["px_mae"]).all()  # the instance's own parameter was used
    with pytest.raises(ConfigError, match="seed"):  # a failure inside the call unregisters too
        api.evaluate(_Argmax(), seed=-1, **{k: v for k, v in TINY.items() if k != "seed"})
    assert "api_test_argmax" not in trackers.available(unlisted=True)


def test_an_unregistered_class_cannot_take_a_registered_label(runs):
    with pytest.raises(ConfigError, match="'dp4' is a registered tracker of another class"):
        api.evaluate(_Argmax(), label="dp4", **TINY)


def test_same_configuration_and_seed_give_the_same_metrics(runs, tmp_path):
    a = api.evaluate("threshold", out=tmp_path / "a", **TINY)
    b = api.evaluate("threshold", out=tmp_path / "b", **TINY)
    timing = ["ms_per_frame"]
    pd.testing.assert_frame_equal(a.drop(columns=timing), b.drop(columns=timing))


@pytest.mark.parametrize("kwargs, message", [
    ({"colour": "red"}, "unknown configuration key 'colour'"),
    ({"trackers": ["dp8"]}, "unknown configuration key 'trackers'"),
    ({"seed": -1}, "`seed` must be an integer >= 0, got -1"),
    ({"render": {"width": 0}}, "render.width"),
])
def test_bad_overrides_are_one_line(runs, kwargs, message):
    with pytest.raises(ConfigError, match=re.escape(message)) as info:
        api.evaluate("dp4", **kwargs)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("tracker, kwargs, message", [
    (42, {}, "`tracker` must be a trackers.Tracker, a registered name or a settings dict"),
    ("no_such_tracker", {}, "unknown tracker 'no_such_tracker'"),
    ({"name": "dp4", "params": {"nope": 1}}, {}, "unknown parameter"),
    ("dp4", {"profile": "nope"}, "unknown profile 'nope'"),
    ("dp4", {"profile": 3}, "`profile` must be a profile name"),
    ("dp4", {"label": 7}, "`label` must be a string, got 7"),
])
def test_bad_arguments_name_themselves(runs, tracker, kwargs, message):
    with pytest.raises(ConfigError, match=re.escape(message)):
        api.evaluate(tracker, **kwargs)


def test_load_run_refuses_what_is_not_a_run(tmp_path):
    with pytest.raises(RunFolderError, match="not a folder"):
        api.load_run(tmp_path / "missing")
    with pytest.raises(RunFolderError, match="summary.json"):
        api.load_run(tmp_path)
    with pytest.raises(ConfigError, match="`path` must be a run folder path"):
        api.load_run(3)


def test_the_api_is_not_the_evaluation_layer():
    import bench.evaluate

    assert not hasattr(bench.evaluate, "evaluate") and callable(api.evaluate)


def _doc_blocks(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def test_the_doc_block_reader_finds_blocks():
    assert _doc_blocks("a\n```python\nx = 1\n```\nb\n```python\ny = 2\n```\n") == ["x = 1\n", "y = 2\n"]


def test_docs_api_examples_run(runs, capsys):
    blocks = _doc_blocks((REPO / "docs" / "api.md").read_text(encoding="utf-8"))
    assert len(blocks) >= 4
    ns = {"__name__": "docs_api"}
    for block in blocks:
        exec(compile(block, "docs/api.md", "exec"), ns)
    out = capsys.readouterr().out
    assert set(ns["df"]["tracker"]) == {"dp4"} and set(ns["soft"]["tracker"]) == {"dp4_soft"}
    assert set(ns["narrow"]["tracker"]) == {"centroid_hw3"} and set(ns["mine"]["tracker"]) == {"row_argmax"}
    assert ns["run"].metrics.shape[0] == 2 and ns["run"].path == pathlib.Path(ns["run_dir"])
    assert "row_argmax" not in trackers.available(unlisted=True)
    assert "ConfigError: evaluate() got an unknown configuration key 'colour'" in out
    assert "ConfigError: `seed` must be an integer >= 0, got -1" in out
    assert "RunFolderError: RUN must be a finished run folder" in out


@pytest.mark.parametrize("kwargs, message", [({"out": 5}, r"`out` must be a path"), ({"force": "yes"}, r"`force` must be"),
                                             ({"quiet": None}, r"`quiet` must be")])
def test_evaluate_refuses_bad_arguments_before_any_work(kwargs, message, tmp_path, monkeypatch):
    from bench.api import evaluate
    from bench.errors import ConfigError

    monkeypatch.chdir(tmp_path)
    with pytest.raises(ConfigError, match=message):
        evaluate("threshold", **kwargs)
    assert not (tmp_path / "results").exists()
