"""The ``learned`` tracker: committed weights, conformance, the forward pass, a tiny training run."""

import subprocess
import sys

import numpy as np
import pytest

import trackers
from trackers import _learned_kernels as lk
from trackers.learned import DEFAULT_WEIGHTS, FORMAT_VERSION, LearnedTracker, WeightsError, load_weights
from trackers.testing import make_stripe_image, parametrize_with_checks


def test_registered_listed_and_weights_committed():
    assert isinstance(trackers.make("learned"), LearnedTracker)
    assert "learned" in trackers.available()
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


def _brute_force_chain(lg, cl, none, jc, sc, cap=8.0):
    """The best chain's score by trying every chain (tiny cases only)."""
    import itertools

    H, K = lg.shape
    best = -np.inf
    for states in itertools.product(range(K + 1), repeat=H):
        node = [none if s == K else lg[r, s] for r, s in enumerate(states)]
        if not np.all(np.isfinite(node)):
            continue
        v = float(np.sum(node))
        for r in range(1, H):
            a, b = states[r - 1], states[r]
            if a < K and b < K:
                v -= jc * min(abs(cl[r, b] - cl[r - 1, a]), cap)
            elif (a == K) != (b == K):
                v -= sc
        best = max(best, v)
    return best


def _chain_score(lg, cl, none, jc, sc, states, cap=8.0):
    K = lg.shape[1]
    st = [K if s < 0 else s for s in states]
    v = sum(none if s == K else lg[r, s] for r, s in enumerate(st))
    for r in range(1, len(st)):
        a, b = st[r - 1], st[r]
        if a < K and b < K:
            v -= jc * min(abs(cl[r, b] - cl[r - 1, a]), cap)
        elif (a == K) != (b == K):
            v -= sc
    return v


@pytest.mark.parametrize("seed", range(6))
def test_decode_finds_the_best_chain_and_without_costs_is_the_threshold_rule(seed):
    rng = np.random.default_rng(seed)
    H, K = 5, 2
    lg = rng.normal(0, 2, (H, K))
    lg[rng.random((H, K)) < 0.2] = -np.inf
    cl = rng.uniform(0, 30, (H, K))
    for jc, sc in ((0.3, 1.0), (0.05, 3.0), (1.0, 0.0)):
        got = lk.decode(lg, cl, -0.4, jc, sc)
        assert _chain_score(lg, cl, -0.4, jc, sc, got) == pytest.approx(_brute_force_chain(lg, cl, -0.4, jc, sc))
    alone = lk.decode(lg, cl, -0.4)
    best = np.argmax(lg, axis=1)
    assert np.array_equal(alone, np.where(lg[np.arange(H), best] >= -0.4, best, -1))


def test_chain_costs_come_from_the_weights_and_zero_costs_keep_the_rule():
    from trackers.learned import candidates, choose

    img, truth = make_stripe_image(seed=3)
    net = load_weights()
    logit, col, base = candidates(img, None, net)
    c0, p0, ok0 = choose(logit, col, base, 0.3)
    c1, p1, ok1 = choose(logit, col, base, 0.3, 0.0, 0.0)
    assert np.array_equal(ok0, ok1) and np.array_equal(c0[ok0], c1[ok1])
    with np.load(DEFAULT_WEIGHTS) as z:
        assert float(z["jump_cost"]) == net["jump_cost"] and float(z["switch_cost"]) == net["switch_cost"]
    plain = LearnedTracker(jump_cost=0.0, switch_cost=0.0, threshold=0.3).track(img)
    W = img.shape[1]
    assert np.array_equal(plain.detected, ok0) and np.allclose(plain.columns[ok0], np.clip(c0[ok0], -0.5, W - 0.5))


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


def test_frames_in_other_units_reach_the_network_in_8_bit_dn():
    img, _ = make_stripe_image(seed=2)
    f = img.astype(np.float64)
    same, _ = lk.in_dn(f)
    assert np.array_equal(same, f)  # 8-bit values pass unchanged (the shipped set's results stay byte for byte)
    view = f * 0.7 + 0.25  # a colour view of an 8-bit photograph: [0, 255], not whole numbers
    assert np.array_equal(lk.in_dn(view)[0], view)
    for other in (img.astype(np.uint16) * 257, f - 300, f * 1e300, f * 1e-300, (f - f.min()) / np.ptp(f)):
        got, _ = lk.in_dn(other)
        assert got.min() == 0 and got.max() == 255
        assert np.allclose(got, (f - f.min()) * 255 / np.ptp(f), rtol=0, atol=1e-9)
    on, off = lk.in_dn(f * 1000, f * 500)  # one map for the pair: the difference keeps its sign
    assert on.max() == 255 and off.min() == 0 and np.all(on >= off)
    blank, bg = lk.in_dn(np.full((4, 5), 7e5), np.full((4, 5), 7e5))
    assert not blank.any() and not bg.any()
    assert np.all(np.isnan(LearnedTracker().track(np.full((40, 50), 1e-300)).columns))


def test_border_candidates_leave_the_inner_ones_unchanged(monkeypatch):
    img, _ = make_stripe_image(seed=4)
    img[:, 0] = 250  # a sharp line on the first column
    feats, cols, base = lk.features(img, None)
    assert feats.shape[1] == lk.K + 2 and np.all(cols[:, lk.K] == 0) and np.all(base[:, lk.K] == 0)
    monkeypatch.setattr(lk, "BORDER_RUN_PX", -1)  # no border candidate at all
    f0, c0, b0 = lk.features(img, None)
    assert np.all(c0[:, lk.K:] == -1)
    # the inner candidates and their features do not depend on the border ones (8-bit results stay as they were)
    assert np.array_equal(c0[:, :lk.K], cols[:, :lk.K]) and np.array_equal(f0[:, :lk.K], feats[:, :lk.K])
    assert np.array_equal(b0[:, :lk.K], base[:, :lk.K], equal_nan=True)
    monkeypatch.undo()
    wide = make_stripe_image(seed=4)[0]
    wide[:, :lk.BORDER_RUN_PX + 1] = 250  # a bright band wider than BORDER_RUN_PX at the border: no candidate
    assert np.all(lk.features(wide, None)[1][:, lk.K] == -1)


def _weights_data():
    with np.load(DEFAULT_WEIGHTS) as z:
        return {k: z[k] for k in z.files}


def _stored_with_bad_crc(path):
    import io
    import zipfile

    buf = io.BytesIO()
    np.savez(buf, **_weights_data())  # stored, not deflated: a flipped byte of w1's data fails its CRC-32
    data = bytearray(buf.getvalue())
    info = {i.filename: i for i in zipfile.ZipFile(io.BytesIO(bytes(data))).infolist()}["w1.npy"]
    data[info.header_offset + 30 + len(info.filename) + 2000] ^= 0xFF
    path.write_bytes(bytes(data))


def _npy_bytes(a):
    import io

    buf = io.BytesIO()
    np.save(buf, a)
    return buf.getvalue()


def _edited(**change):
    def write(path):
        data = {k: v for k, v in _weights_data().items() if k not in change or change[k] is not None}
        data.update({k: v for k, v in change.items() if v is not None})
        np.savez(path, **data)
    return write


_BAD_WEIGHTS = [  # (case, writer, what the one line says)
    ("empty", lambda p: p.write_bytes(b""), "an empty file"),
    ("truncated", lambda p: p.write_bytes(DEFAULT_WEIGHTS.read_bytes()[:5000]), "not a readable .npz archive"),
    ("bad CRC", _stored_with_bad_crc, "`w1` is unreadable (BadZipFile: Bad CRC-32"),
    (".npy named .npz", lambda p: p.write_bytes(_npy_bytes(np.zeros(3))), "one .npy array, not an .npz archive"),
    ("text", lambda p: p.write_text("weights"), "not an .npz archive"),
    ("k = 0", _edited(k=np.int64(0)), "`k` must be >= 1, got 0"),
    ("k = 1e9", _edited(k=np.int64(10**9)), "`k` must be <= 64, got 1000000000"),
    ("k a float", _edited(k=np.float64(6.0)), "`k` must be an integer, got dtype float64"),
    ("w2 of the wrong shape", _edited(w2=np.zeros((3, 4), np.float32)), "`w2` has shape (3, 4), expected (H1, H2)"),
    ("w1 all NaN", _edited(w1=np.full((163, 32), np.nan, np.float32)), "`w1` holds 5216 NaN or infinite"),
    ("w1 beyond float32", _edited(w1=np.full((163, 32), 1e300)), "`w1` holds 5216 NaN or infinite"),
    ("w1 of strings", _edited(w1=np.full((163, 32), "a")), "`w1` must hold real numbers"),
    ("threshold 5", _edited(threshold=np.float64(5)), "`threshold` must be <= 1, got 5.0"),
    ("jump_cost NaN", _edited(jump_cost=np.float64(np.nan)), "`jump_cost` must be a real number, got nan"),
    ("switch_cost < 0", _edited(switch_cost=np.float64(-1)), "`switch_cost` must be >= 0"),
    ("sd 0", _edited(sd=np.zeros(163, np.float32)), "`sd` must be > 0 everywhere"),
    ("w3 missing", _edited(w3=None), "lack `w3`"),
    ("layout not JSON", _edited(layout=np.str_("{x")), "`layout` is not valid JSON"),
    ("provenance a list", _edited(provenance=np.str_("[1]")), "`provenance` must be a JSON object"),
    ("provenance nested too deeply", _edited(provenance=np.str_("[" * 50000 + "]" * 50000)),
     "`provenance` is not valid JSON (RecursionError"),
    ("format_version a string", _edited(format_version=np.str_("1")), "`format_version` must be an integer"),
    ("a hidden layer of 5000", _edited(w1=np.zeros((163, 5000), np.float32), b1=np.zeros(5000, np.float32),
                                        w2=np.zeros((5000, 16), np.float32)), "`w1` has 5000 columns"),
    ("a folder", lambda p: p.mkdir(), "are not a regular file (a folder)"),
    ("a FIFO", lambda p: __import__("os").mkfifo(p), "are not a regular file (a FIFO)"),
]


@pytest.mark.parametrize("case, write, message", _BAD_WEIGHTS, ids=[c[0] for c in _BAD_WEIGHTS])
def test_bad_weights_are_refused_whole_before_any_frame_in_one_line(tmp_path, case, write, message):
    path = tmp_path / "w.npz"
    write(path)
    tracker = trackers.make("learned", weights=str(path))
    with pytest.raises(WeightsError) as err:
        tracker.validate_params()  # what a configuration runs before any render (bench.config.tracker_specs)
    msg = str(err.value)
    assert message in msg and str(path) in msg and "\n" not in msg and len(msg) < 400
    with pytest.raises(WeightsError):
        tracker.track(make_stripe_image()[0])


def test_a_zip_bomb_is_refused_by_its_declared_size(tmp_path):
    import io

    buf = io.BytesIO()
    np.savez_compressed(buf, **{**_weights_data(), "w1": np.zeros((163, 500_000), np.float32)})  # 326 MB of zeros
    (tmp_path / "w.npz").write_bytes(buf.getvalue())
    with pytest.raises(WeightsError, match="bytes of arrays once uncompressed"):
        load_weights(tmp_path / "w.npz")
