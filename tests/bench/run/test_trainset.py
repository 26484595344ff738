"""Training sets from the renderer (``stripebench trainset``)."""

import json

import numpy as np
import pytest

from bench.errors import InputError
from bench.run import trainset as ts


def test_a_training_set_and_the_paper_run_share_no_frame():
    units = ts.plan(12, 3, seed=1)
    paper = ts.paper_frames()
    assert paper  # the paper run's frames: seed 0
    planned = {ts.frame_key(u["params"], a) for u in units for a in u["angles_deg"]}
    assert len(planned) == 36 and not planned & paper
    assert all(u["params"]["seed"] >= ts.SEED_BASE for u in units)


def test_plan_refuses_a_paper_frame(monkeypatch):
    key = next(iter(ts.paper_frames()))
    monkeypatch.setattr(ts, "frame_key", lambda params, a: key)
    with pytest.raises(InputError, match="paper run"):
        ts.plan(1, 1, seed=1)


def test_draws_are_seeded_and_cover_the_field_classes():
    a = [ts.draw_unit(3, u) for u in range(60)]
    assert a == [ts.draw_unit(3, u) for u in range(60)]
    assert {p["scene"] for p in a} == set(ts.OBJECTS)
    assert {"rgb"} <= {p.get("camera") for p in a} and any("jpeg_quality" in p for p in a)
    assert len({p["material"] for p in a}) >= 6


@pytest.mark.slow
def test_streamed_resumable_training_set(tmp_path, monkeypatch):
    root = ts.build_trainset(tmp_path / "ts", n_units=1, angles_per_unit=1, seed=2, noise_draws=2, width=64,
                             height=60, quiet=True)
    doc, rows = ts.read_trainset(root)
    assert len(rows) == 2 and doc["seed"] == 2
    img, off, truth = ts.tracker_view(root, rows[0])
    assert img.shape == off.shape == (60, 64) and truth.shape == (60,)
    # a rerun renders nothing: every frame is finished
    import scenes.scene

    monkeypatch.setattr(scenes.scene.Scene, "render", lambda *a, **k: (_ for _ in ()).throw(AssertionError))
    ts.build_trainset(tmp_path / "ts", n_units=1, angles_per_unit=1, seed=2, noise_draws=2, width=64, height=60,
                      quiet=True)
    with pytest.raises(InputError, match="other settings"):
        ts.build_trainset(tmp_path / "ts", n_units=1, angles_per_unit=2, seed=2, width=64, height=60, quiet=True)
