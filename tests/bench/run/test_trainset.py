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
    a = [ts.draw_unit(3, u, draws=1) for u in range(60)]
    assert a == [ts.draw_unit(3, u, draws=1) for u in range(60)]
    assert {p["scene"] for p in a} == set(ts.OBJECTS)
    assert {"rgb"} <= {p.get("camera") for p in a} and any("jpeg_quality" in p for p in a)
    assert len({p["material"] for p in a}) >= 6


def test_rules_1_are_the_first_weights_draws():
    # the first committed weights' training set (seed 1) was drawn by these rules before they had a number
    p = ts.draw_unit(1, 0, draws=1)
    assert (p["scene"], p["material"], p["background"], p["support"], p["ambient_illuminant"]) == (
        "sphere", "matte", "wall", "none", "A")
    assert round(p["ambient_lux"], 6) == 442.967978 and round(p["line_fwhm_mrad"], 6) == 2.845358


def test_rules_2_draw_levels_per_frame_with_saturated_stripes_and_wide_lines():
    units = ts.plan(40, 4, seed=2, noise_draws=2, draws=2)
    assert units == ts.plan(40, 4, seed=2, noise_draws=2, draws=2)
    frames = [f for u in units for per_angle in u["photometry"] for f in per_angle]
    assert len(frames) == 40 * 4 * 2 and all(set(f) == set(ts.PHOTOMETRY_KEYS) for f in frames)
    assert not any(k in u["params"] for u in units for k in ts.PHOTOMETRY_KEYS)
    saturated = [f["laser_power_mw"] >= 5 and f["exposure_ms"] >= 10 for f in frames]
    assert 0.25 < np.mean(saturated) < 0.5
    assert any(u["params"]["line_fwhm_mrad"] > 4 for u in units)
    assert any(f["jpeg_quality"] is not None for f in frames) and max(f["defocus_px"] for f in frames) > 1.0
    # the two noise draws of an angle differ in level, not only in noise
    assert any(pa[0] != pa[1] for u in units for pa in u["photometry"])
    with pytest.raises(InputError, match="draw rules"):
        ts.draw_unit(2, 0, draws=4)


def test_rules_3_are_rules_2_with_a_distractor_in_half_the_units():
    from scenes.distractors import DISTRACTORS

    two = [ts.draw_unit(5, u, draws=2) for u in range(80)]
    three = [ts.draw_unit(5, u, draws=3) for u in range(80)]
    assert all({k: v for k, v in b.items() if k != "distractor"} == a for a, b in zip(two, three))
    kinds = [p.get("distractor") for p in three]
    assert 0.35 < np.mean([k is not None for k in kinds]) < 0.65
    assert {k for k in kinds if k} == set(DISTRACTORS[1:])
    units = ts.plan(6, 2, seed=5, draws=3)  # the scenes accept them
    assert any("distractor" in u["params"] for u in units)


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


@pytest.mark.slow
def test_a_damaged_frame_record_is_rendered_again_with_one_line(tmp_path, capsys):
    kw = dict(n_units=1, angles_per_unit=1, seed=2, noise_draws=1, width=64, height=60, quiet=True)
    root = ts.build_trainset(tmp_path / "ts", **kw)
    (record,) = (root / "images").glob("*.json")
    good = record.read_text()
    capsys.readouterr()
    for damage in ("{not json", "[1, 2]", '{"frame": "x"}'):
        record.write_text(damage)
        ts.build_trainset(tmp_path / "ts", **kw)
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "frame record" in err and "rendering that frame again" in err, err
        assert record.read_text() == good  # rendered again: the same frame, the same record


@pytest.mark.parametrize("rgb", [False, True])
def test_tracker_view_shrinks_the_stored_frames_and_their_truth(tmp_path, rgb, tiny_trainset):
    from bench.evaluate.pixels import downscale, select_channel

    row, img, off = tiny_trainset(tmp_path, rgb=rgb)
    on1, off1, t1 = ts.tracker_view(tmp_path, row, "laser")
    on2, off2, t2 = ts.tracker_view(tmp_path, row, "laser", downscale=2)
    assert on1.shape == (6, 8) and on2.shape == (3, 4)
    small = downscale(img, 2)
    assert np.array_equal(on2, select_channel(small, "r", "red") if rgb else small)
    assert np.array_equal(off2, downscale(off, 2)[..., 0] if rgb else downscale(off, 2))
    assert np.allclose(t1[:4], 2.5) and np.isnan(t1[4:]).all()
    # rows 0-1 and 2-3 keep a stripe, at (2.5 - 0.5) / 2 = 1.0; rows 4-5 have none
    assert np.allclose(t2[:2], 1.0) and np.isnan(t2[2])
