"""Scans: fault tolerance and resuming, with a small synthetic scene."""

import numpy as np
import pytest

import trackers
from bench.run.scan import run_scan
from bench.store.checkpoint import ScanResult
from scenes import Frame, Truth
from trackers import Track, Tracker
from trackers.testing import make_stripe_image


class SyntheticScene:
    """Stands in for scenes.Scene: analytic stripe frames, counted renders."""

    name = "synthetic"

    def __init__(self, height=40, width=50):
        self.rig = _SmallRig(width, height)
        self.params = {"width": width, "height": height}
        self.renders = 0

    def render(self, angle, spp=None, seed=None):
        self.renders += 1
        H, W = self.rig.height, self.rig.width
        img, cols = make_stripe_image(H, W, seed=int(1000 + angle * 10))
        truth = Truth(cols, np.zeros((H, 3)), np.ones(H, bool))
        return Frame(img, np.full_like(img, 10), img.astype(np.float32), img.astype(np.float32), truth, float(angle),
                     "synthetic")


class _SmallRig:
    def __init__(self, width, height):
        self.width, self.height = width, height


class Raises(Tracker):
    name = "raises"

    def _track(self, image, background):
        raise RuntimeError("boom")


class WrongShape(Tracker):
    name = "wrong-shape"

    def _track(self, image, background):
        return Track.empty(image.shape[0] + 2)


class Outside(Tracker):
    name = "outside"

    def _track(self, image, background):
        return Track(np.full(image.shape[0], 1e4), np.ones(image.shape[0]))


class NotATrack(Tracker):
    name = "not-a-track"

    def _track(self, image, background):
        return np.zeros(image.shape[0])


def test_scan_goes_on_past_failing_trackers_and_resumes(tmp_path):
    scene = SyntheticScene()
    trs = {"centroid": trackers.make("centroid"), "raises": Raises(), "outside": Outside()}
    ckpt = tmp_path / "scan.npz"
    res = run_scan("syn", scene, [0.0, 1.0, 2.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    assert res.complete and scene.renders == 3
    assert (res.status["raises"] == 1).all() and (res.status["outside"] == 3).all()
    assert (res.status["centroid"] == 0).all() and np.nanmax(np.abs(res.columns["centroid"] - res.truth_columns)) < 1
    # the checkpoint holds everything; a rerun renders nothing
    again = run_scan("syn", scene, [0.0, 1.0, 2.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    assert scene.renders == 3
    assert np.array_equal(again.columns["centroid"], res.columns["centroid"], equal_nan=True)
    assert again.messages["raises"][0].startswith("RuntimeError: boom")


def test_interrupted_scan_keeps_finished_frames(tmp_path):
    class Interrupting(SyntheticScene):
        def render(self, angle, spp=None, seed=None):
            if self.renders == 2:
                raise KeyboardInterrupt
            return super().render(angle, spp, seed)

    scene = Interrupting()
    ckpt = tmp_path / "scan.npz"
    trs = {"threshold": trackers.make("threshold")}
    with pytest.raises(KeyboardInterrupt):
        run_scan("syn", scene, [0.0, 1.0, 2.0, 3.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    from bench.store.files import load_npz

    saved = ScanResult.from_arrays("syn", load_npz(ckpt))
    assert saved.done.tolist() == [True, True, False, False]
    fresh = SyntheticScene()
    res = run_scan("syn", fresh, [0.0, 1.0, 2.0, 3.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    assert fresh.renders == 2 and res.complete  # only the two missing frames


def test_checkpoint_of_other_angles_is_not_reused(tmp_path):
    scene = SyntheticScene()
    ckpt = tmp_path / "scan.npz"
    trs = {"threshold": trackers.make("threshold")}
    run_scan("syn", scene, [0.0, 1.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    run_scan("syn", scene, [0.0, 1.5], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    assert scene.renders == 4


@pytest.mark.slow
def test_a_checkpoint_made_with_other_tracker_parameters_is_not_resumed(tmp_path):
    import scenes

    scene = scenes.make("plane", width=64, height=60, spp=1, ambient_spp=1)
    ckpt = tmp_path / "scan.npz"
    calls = []
    original = scene.render
    scene.render = lambda *a, **kw: calls.append(1) or original(*a, **kw)
    run_scan("p", scene, [0.0, 0.5], {"threshold": trackers.make("threshold")}, spp=1, seed=0, checkpoint=ckpt,
             progress=False)
    run_scan("p", scene, [0.0, 0.5], {"threshold": trackers.make("threshold")}, spp=1, seed=0, checkpoint=ckpt,
             progress=False)
    assert len(calls) == 2  # resumed: nothing rendered again
    run_scan("p", scene, [0.0, 0.5], {"threshold": trackers.make("threshold", k_sigma=9.0)}, spp=1, seed=0,
             checkpoint=ckpt, progress=False)
    assert len(calls) == 4  # other parameters: computed afresh


@pytest.mark.parametrize("damage", ["columns of another height", "missing array", "bit flip"])
def test_a_damaged_checkpoint_is_reported_in_one_line_and_recomputed(damage, tmp_path):
    from bench.store.files import load_npz, save_npz

    scene = SyntheticScene()
    ckpt = tmp_path / "scan.npz"
    trs = {"threshold": trackers.make("threshold")}
    first = run_scan("syn", scene, [0.0, 1.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    arrays = load_npz(ckpt)
    if damage == "columns of another height":
        arrays["columns/threshold"] = np.zeros((2, 7))
        save_npz(ckpt, **arrays)
    elif damage == "missing array":
        del arrays["scores/threshold"]
        save_npz(ckpt, **arrays)
    else:
        import zipfile

        data = bytearray(ckpt.read_bytes())
        with zipfile.ZipFile(ckpt) as zf:  # a byte inside the largest member's data (CRC-checked), not a header
            zi = max(zf.infolist(), key=lambda i: i.compress_size)
        off = zi.header_offset
        start = off + 30 + int.from_bytes(data[off + 26:off + 28], "little") + int.from_bytes(data[off + 28:off + 30],
                                                                                              "little")
        data[start + zi.compress_size // 2] ^= 0xFF
        ckpt.write_bytes(bytes(data))
    notes = []
    fresh = SyntheticScene()
    res = run_scan("syn", fresh, [0.0, 1.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False,
                      say=notes.append)
    assert fresh.renders == 2 and len(notes) == 1 and "recomputing" in notes[0]
    np.testing.assert_array_equal(res.columns["threshold"], first.columns["threshold"])


def test_a_checkpoint_edited_on_disk_is_recomputed_with_one_line(tmp_path):
    from bench.store.files import load_npz, save_npz

    scene = SyntheticScene()
    ckpt = tmp_path / "scan.npz"
    trs = {"threshold": trackers.make("threshold")}
    first = run_scan("syn", scene, [0.0, 1.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False)
    arrays = load_npz(ckpt)
    arrays["columns/threshold"] = arrays["columns/threshold"] + 3.0  # every column shifted 3 px
    save_npz(ckpt, **arrays)
    notes = []
    fresh = SyntheticScene()
    res = run_scan("syn", fresh, [0.0, 1.0], trs, spp=1, seed=0, checkpoint=ckpt, progress=False, say=notes.append)
    assert fresh.renders == 2 and len(notes) == 1 and "edited or damaged" in notes[0] and "recomputing" in notes[0]
    np.testing.assert_array_equal(res.columns["threshold"], first.columns["threshold"])


def test_a_directory_in_the_checkpoints_place_is_removed_and_the_scan_computed(tmp_path):
    ckpt = tmp_path / "scan.npz"
    (ckpt / "junk").mkdir(parents=True)
    notes = []
    scene = SyntheticScene()
    res = run_scan("syn", scene, [0.0, 1.0], {"threshold": trackers.make("threshold")}, spp=1, seed=0,
                   checkpoint=ckpt, progress=False, say=notes.append)
    assert res.complete and ckpt.is_file()
    assert len(notes) == 1 and "a directory, not a file (removed)" in notes[0]
