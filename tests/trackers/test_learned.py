"""The ``learned`` tracker: committed weights, conformance, the forward pass, a tiny training run."""

import subprocess
import sys

import numpy as np
import pytest

import trackers
from trackers import _learned_kernels as lk
from trackers.learned import DEFAULT_WEIGHTS, FORMAT_VERSION, LearnedTracker, WeightsError, load_weights
from trackers.testing import make_stripe_image, parametrize_with_checks


def test_registered_unlisted_and_weights_committed():
    assert isinstance(trackers.make("learned"), LearnedTracker)
    assert "learned" in trackers.available(unlisted=True) and "learned" not in trackers.available()
    assert DEFAULT_WEIGHTS.is_file() and DEFAULT_WEIGHTS.stat().st_size <= 5 * 2**20
    net = load_weights()
    assert 0 < net["threshold"] < 1 and net["provenance"]["trained_on"].startswith("renders only")


@parametrize_with_checks([LearnedTracker()])
def test_conformance(tracker, check):
    check(tracker)


def test_other_format_version_is_refused_in_one_line(tmp_path):
    with np.load(DEFAULT_WEIGHTS) as z:
        data = {k: z[k] for k in z.files}
    data["format_version"] = np.int64(FORMAT_VERSION + 1)
    bad = tmp_path / "v2.npz"
    np.savez(bad, **data)
    with pytest.raises(WeightsError) as err:
        LearnedTracker(weights=str(bad)).track(make_stripe_image()[0])
    msg = str(err.value)
    assert "\n" not in msg and f"format version {FORMAT_VERSION + 1}" in msg
    with pytest.raises(WeightsError, match="cannot read"):
        load_weights(tmp_path / "missing.npz")


def test_import_stays_light():
    code = ("import sys, trackers, trackers.learned, trackers._learned_kernels; "
            "print(sorted(m for m in ('jax', 'flax', 'optax', 'mitsuba', 'matplotlib') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_features_are_flip_symmetric():
    img, _ = make_stripe_image(seed=5)
    a, ca, ba = lk.features(img, None)
    b, cb, bb = lk.features(img[::-1], None)
    assert np.array_equal(a[::-1], b) and np.array_equal(ca[::-1], cb)


def _synthetic_frames(seeds):
    """Stripes of random strength in the top half of each frame, nothing in the bottom half."""
    frames = []
    for s in seeds:
        rng = np.random.default_rng(s)
        img, t = make_stripe_image(seed=s, peak=float(rng.uniform(25, 200)))
        img, t = img.copy(), t.copy()
        img[48:] = np.clip(np.rint(rng.normal(10, 2, img[48:].shape)), 0, 255).astype(np.uint8)
        t[48:] = np.nan
        frames.append((img, None, t))
    return frames


def test_numpy_forward_equals_flax_and_a_tiny_training_run_learns_a_stripe(jax_child):
    if not jax_child:  # ran in a child process (tests/conftest.py)
        return
    from bench.studies.train import (HyperParams, choose_threshold, evaluate_frames, flax_forward,
                                     samples_from_frames, train_network)

    train = samples_from_frames(_synthetic_frames(range(8)))
    val = samples_from_frames(_synthetic_frames(range(100, 103)))
    hp = HyperParams(epochs=4, batch=256, seed=0)
    net, curves = train_network(train, val, hp)
    assert curves["train_loss"][-1] < 0.5 * curves["train_loss"][0]
    assert curves["val_loss"][-1] < curves["val_loss"][0]
    x = val[0][:2000]
    np.testing.assert_allclose(lk.mlp_forward(x, net), flax_forward(net, x), rtol=1e-5, atol=1e-5)
    table = evaluate_frames(_synthetic_frames(range(200, 204)), {**net, "k": hp.k}, hp.thresholds)
    best = table[choose_threshold(table)]
    # held-out synthetic frames: at least 95 % of the stripe rows hit, at most 2 % false reports
    assert best["hit_rate"] >= 0.95 and best["false_report_rate"] <= 0.02, best
