"""Scan checkpoints: format 2 with a checksum; every damaged, edited or foreign file refused with its reason."""

import pathlib

import numpy as np
import pytest

from bench.store.checkpoint import FORMAT, STATUS, ScanResult, read_checkpoint, verify_checkpoint, write_checkpoint
from bench.store.files import array_checksum, load_npz, save_npz


def _scan(F=3, H=5):
    res = ScanResult.empty("k", np.linspace(-2.0, 2.0, F), H, ["a", "b"])
    rng = np.random.default_rng(0)
    res.truth_columns[:] = rng.uniform(0, 40, (F, H))
    res.truth_points_cm[:] = rng.normal(size=(F, H, 3))
    res.on_object[:] = rng.random((F, H)) > 0.5
    for n in res.columns:
        res.columns[n][:] = res.truth_columns + rng.normal(size=(F, H))
        res.scores[n][:] = 1.0
        res.seconds[n][:] = 0.01
    res.columns["a"][0, 1] = np.nan  # a missed row is NaN, not damage
    res.status["b"][1] = 1
    res.messages["b"][1] = "RuntimeError: boom"
    res.done[:2] = True
    res.variant, res.width, res.render_seconds, res.fingerprint = "v", 50, 1.5, "fp"
    return res


def test_a_checkpoint_round_trips_exactly(tmp_path):
    res = _scan()
    write_checkpoint(tmp_path / "c.npz", res)
    back, why = read_checkpoint(tmp_path / "c.npz", "k")
    assert why is None and back.key == "k" and back.fingerprint == "fp" and back.messages["b"][1] == "RuntimeError: boom"
    for n in res.columns:
        np.testing.assert_array_equal(back.columns[n], res.columns[n])
    np.testing.assert_array_equal(back.done, res.done)
    raw = load_npz(tmp_path / "c.npz")
    assert int(raw["format"]) == FORMAT and str(raw.pop("checksum")) == array_checksum(raw)
    assert verify_checkpoint(tmp_path / "c.npz") is None


def test_columns_shifted_on_disk_are_caught_by_the_checksum(tmp_path):
    p = tmp_path / "c.npz"
    write_checkpoint(p, _scan())
    arrays = load_npz(p)
    arrays["columns/a"] = arrays["columns/a"] + 3.0  # edited: every column 3 px to the right, old checksum kept
    save_npz(p, **arrays)
    res, why = read_checkpoint(p)
    assert res is None and why.startswith("edited or damaged") and "checksum" in why


def test_a_format_1_checkpoint_is_not_resumed(tmp_path):
    p = tmp_path / "c.npz"
    save_npz(p, **_scan().to_arrays())  # what the code before formats wrote: no format, no checksum
    res, why = read_checkpoint(p)
    assert res is None and why.startswith("of format 1")


def _resigned(p, **changes):
    """Rewrite the checkpoint with ``changes`` and a checksum that matches them (a foreign writer)."""
    arrays = load_npz(p)
    arrays.pop("checksum")
    arrays.update(changes)
    save_npz(p, **arrays, checksum=np.array(array_checksum(arrays)))


@pytest.mark.parametrize("change, reason", [
    ({"columns/a": np.full((3, 5), np.inf)}, "infinite"),
    ({"angles": np.array([0.0, np.nan, 1.0])}, "'angles' holds NaN"),
    ({"status/b": np.array([0, 9, 0])}, "unknown status 9"),
    ({"columns/b": np.zeros((3, 7))}, "expected (3, 5)"),
    ({"render_seconds": np.array(-1.0)}, "not a time"),
])
def test_values_a_scan_cannot_hold_are_refused_even_with_a_good_checksum(change, reason, tmp_path):
    p = tmp_path / "c.npz"
    write_checkpoint(p, _scan())
    _resigned(p, **change)
    res, why = read_checkpoint(p)
    assert res is None and why.startswith("damaged") and reason in why, why


def test_another_format_number_is_refused(tmp_path):
    p = tmp_path / "c.npz"
    write_checkpoint(p, _scan())
    _resigned(p, format=np.array(FORMAT + 1))
    res, why = read_checkpoint(p)
    assert res is None and why.startswith(f"of format {FORMAT + 1}")


def test_a_directory_in_the_checkpoints_place_is_reported_and_removed_on_request(tmp_path):
    p = tmp_path / "c.npz"
    (p / "inner").mkdir(parents=True)
    assert read_checkpoint(p) == (None, "a directory, not a file")
    assert p.is_dir()  # without clear_bad nothing is removed (pending_frames only looks)
    assert read_checkpoint(p, clear_bad=True) == (None, "a directory, not a file (removed)")
    assert not p.exists()
    write_checkpoint(p, _scan())
    assert read_checkpoint(p)[0] is not None


def test_every_status_track_frame_gives_is_one_a_checkpoint_keeps(tmp_path):
    import re

    from bench.run import track

    codes = {int(c) for c in re.findall(r"TrackResult\(nan, nan, [^,]+, (\d+),", pathlib.Path(track.__file__).read_text())}
    assert codes and codes <= set(STATUS) and 0 in STATUS
    for code in sorted(STATUS):
        res = _scan()
        res.status["b"][0] = code
        write_checkpoint(tmp_path / f"{code}.npz", res)
        assert read_checkpoint(tmp_path / f"{code}.npz")[0] is not None
    res = _scan()
    res.status["b"][0] = max(STATUS) + 1
    write_checkpoint(tmp_path / "unknown.npz", res)
    assert read_checkpoint(tmp_path / "unknown.npz")[0] is None


def test_truncated_or_garbage_files_are_unreadable(tmp_path):
    p = tmp_path / "c.npz"
    write_checkpoint(p, _scan())
    p.write_bytes(p.read_bytes()[:100])
    res, why = read_checkpoint(p)
    assert res is None and why.startswith("unreadable (")
    assert read_checkpoint(tmp_path / "missing.npz") == (None, None)
