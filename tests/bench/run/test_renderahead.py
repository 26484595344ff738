"""The render-ahead helper: same results, frames rendered by the helper, nothing left running."""

import copy
import json

import psutil
import pytest

import scenes
from bench.run import renderahead
from bench.config import parse
from bench.run.experiment import run

#: the three experiments of the same-results test (on the conftest's GATE configuration): two path-traced,
#: one polished (its light-traced pass runs on one thread, where the helper gains)
THREE_EXPERIMENTS = [
    {"scene": "cone", "material": "patchy", "n_angles": 3},
    {"scene": "plane", "material": "absorbing", "n_angles": 2},
    {"scene": "cone", "material": "polished", "n_angles": 3, "background": "none", "support": "table"},
]


def _children() -> set[int]:
    """This process's child processes, less multiprocessing's resource tracker (it lives as long as we do)."""
    out = set()
    for c in psutil.Process().children(recursive=True):
        try:
            if "resource_tracker" not in " ".join(c.cmdline()):
                out.add(c.pid)
        except psutil.NoSuchProcess:
            pass
    return out


def test_reason_off():
    on = [scenes.make("plane", width=64, height=60), scenes.make("cone", width=64, height=60)]
    assert renderahead.reason_off(True, on, cores=2) is None
    assert renderahead.reason_off(False, on, cores=2) == "turned off"
    assert renderahead.reason_off(True, on, cores=1) == "1 core"
    assert renderahead.reason_off(True, on[:1], cores=4) == "one experiment"
    no_cache = [on[0], scenes.make("cone", width=64, height=60, cache=False)]
    assert renderahead.reason_off(True, no_cache, cores=2) == "render cache off"


@pytest.mark.parametrize("kwargs, message", [
    ({"threads": 0}, r"`threads` must be an integer >= 1, got 0"),
    ({"nice": 20}, r"`nice` must be an integer 0 .. 19, got 20"),
    ({"pending": [[True]]}, r"`pending` must hold one flag per frame"),
])
def test_bad_arguments_name_the_argument(kwargs, message):
    scene = scenes.make("plane", width=64, height=60)
    with pytest.raises(ValueError, match=message):
        renderahead.RenderAhead([scene], [[0.0, 1.0]], 0, **kwargs)


@pytest.mark.slow
def test_same_results_with_and_without_and_the_helper_renders(tmp_path, monkeypatch, gate_dict):
    """Cold caches: the same metrics and samples, byte for byte; the helper rendered frames the run used;
    its worker process is gone afterwards."""
    start = renderahead.RenderAhead.start

    def start_and_let_it_work(self):  # a tiny run outpaces the helper's start: give it a head start
        self.nice = 0
        started = start(self)
        assert started and self.wait(2, timeout_s=180) >= 1
        return started

    monkeypatch.setattr(renderahead.RenderAhead, "start", start_and_let_it_work)
    monkeypatch.setattr(renderahead, "MIN_PIXEL_SAMPLES", 0)  # tiny frames: start it all the same
    before = _children()
    outs = {}
    for on in (True, False):
        monkeypatch.setenv("STRIPEBENCH_CACHE_DIR", str(tmp_path / f"cache-{on}"))
        three = {**gate_dict, "name": "renderahead", "seed": 3, "experiments": copy.deepcopy(THREE_EXPERIMENTS)}
        outs[on] = run(parse({**three, "render_ahead": on}), tmp_path / f"run-{on}",
                       progress=False, quiet=True)
        assert _children() <= before, "the helper's worker is still running"
    for name in ("metrics.csv", "samples.csv"):
        assert (outs[True] / name).read_bytes() == (outs[False] / name).read_bytes(), name
    ra = json.loads((outs[True] / "summary.json").read_text())["render_ahead"]
    assert ra["started"] and ra["error"] == "" and ra["frames"] == 8
    assert 1 <= ra["used"] <= ra["rendered"] <= 8 and ra["stop_s"] < 30
    assert json.loads((outs[False] / "summary.json").read_text())["render_ahead"] == {"off": "turned off"}


@pytest.mark.slow
def test_stop_kills_a_busy_helper_at_once(tmp_path, monkeypatch):
    """The run never waits for the helper's current frame: stopping it mid-frame takes seconds, not the frame."""
    monkeypatch.setenv("STRIPEBENCH_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(renderahead, "MIN_PIXEL_SAMPLES", 0)
    slow = scenes.make("cone", material="polished", width=256, height=240, spp=64, ambient_spp=1)
    other = scenes.make("plane", width=64, height=60, spp=1, ambient_spp=1)
    before = _children()
    helper = renderahead.RenderAhead([other, slow], [[0.0, 1.0], [-1.0, 0.0, 1.0]], 0, nice=0)
    assert helper.start()
    try:
        helper.wait(1, timeout_s=180)  # its first (slow) frame is done: it is busy with the next one
    finally:
        result = helper.stop()
    assert result["started"] and result["stop_s"] < 10
    assert _children() <= before
    assert "of 5 frames rendered by the helper" in helper.summary_line()


@pytest.mark.slow
def test_a_cached_run_starts_no_helper(tiny_run):
    """Every frame of the session's tiny run is cached: no helper process is started for it again."""
    from bench.run.plan import angles_for, scene_for

    out, cfg = tiny_run
    plan = [(scene_for(e, cfg), e) for e in cfg.experiments]
    helper = renderahead.RenderAhead([s for s, _ in plan], [angles_for(e, s) for s, e in plan], cfg.seed)
    assert helper.start() is False
    assert helper.stop() == {"frames": 5, "rendered": 0, "used": 0, "started": False, "why": "cached"}
    assert helper.summary_line() == "render-ahead: not needed, every one of the 5 frames was cached or done"


def test_little_to_render_starts_no_helper(tmp_path, monkeypatch):
    """Below MIN_PIXEL_SAMPLES of uncached work the helper's fixed cost would outweigh it: not started."""
    monkeypatch.setenv("STRIPEBENCH_CACHE_DIR", str(tmp_path / "cache"))
    plane = scenes.make("plane", width=64, height=60, spp=2)
    helper = renderahead.RenderAhead([plane, plane], [[0.0, 1.0], [2.0]], 0)
    assert helper.start() is False
    assert helper.stop()["why"] == "little to render (3 frames, 2.3e+04 pixel-samples < 4e+07)"
    assert helper.summary_line().startswith("render-ahead: not started, little to render")
