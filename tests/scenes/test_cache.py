import os

import numpy as np
import pytest

from scenes import cache as C


def test_key_is_stable_and_sensitive():
    a = C.key({"scene": "cone", "angle": 0.1, "spp": 16})
    assert a == C.key({"spp": 16, "angle": 0.1, "scene": "cone"})
    assert a != C.key({"scene": "cone", "angle": 0.1 + 1e-15, "spp": 16})
    assert a != C.key({"scene": "cone", "angle": 0.1, "spp": 17})
    assert len(a) == 64


def test_round_trip_and_layout(tmp_path):
    k = C.key({"x": 1})
    arrays = {"laser": np.arange(6, dtype=np.float32).reshape(2, 3), "on_object": np.array([True, False])}
    p = C.store(tmp_path, k, arrays)
    assert p.parent.name == k[:2] and p.name == f"{k}.npz"
    back = C.load(tmp_path, k)
    assert set(back) == set(arrays)
    assert all(np.array_equal(back[n], arrays[n]) and back[n].dtype == arrays[n].dtype for n in arrays)
    assert not [f for f in os.listdir(p.parent) if f.startswith(".tmp-")]


def test_missing_or_corrupt_files_read_as_absent(tmp_path):
    k = C.key({"y": 2})
    assert C.load(tmp_path, k) is None
    p = C.store(tmp_path, k, {"a": np.zeros(3)})
    p.write_bytes(p.read_bytes()[:20])
    assert C.load(tmp_path, k) is None
    C.store(tmp_path, k, {"a": np.ones(3)})  # overwritten in place
    assert np.array_equal(C.load(tmp_path, k)["a"], np.ones(3))


def test_cache_root_resolution(tmp_path, monkeypatch):
    monkeypatch.setenv(C.ENV_CACHE_DIR, str(tmp_path / "env"))
    assert C.cache_root() == tmp_path / "env"
    assert C.cache_root(tmp_path / "arg") == tmp_path / "arg"
    monkeypatch.delenv(C.ENV_CACHE_DIR)
    assert C.cache_root().parts[-2:] == (".cache", "stripebench")


def _entry(H=4, W=5):
    return {"laser": np.zeros((H, W), np.float32), "ambient": np.zeros((H, W), np.float32),
            "columns": np.zeros(H), "points_cm": np.zeros((H, 3)), "on_object": np.zeros(H, bool)}


def test_an_entry_stored_under_another_key_is_reported_and_ignored(tmp_path, capsys):
    a, b = C.key({"a": 1}), C.key({"b": 2})
    pa = C.store(tmp_path, a, _entry())
    pb = C._path(tmp_path, b)
    pb.parent.mkdir(parents=True, exist_ok=True)
    pb.write_bytes(pa.read_bytes())  # a's file in b's place
    assert C.load(tmp_path, b) is None
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "render cache entry" in err[0] and "re-rendering" in err[0]
    back = C.load(tmp_path, a)
    assert "__key__" not in back and set(back) == set(_entry())


def test_an_entry_with_arrays_of_the_wrong_shape_is_reported_and_ignored(tmp_path, capsys):
    k = C.key({"c": 3})
    bad = {**_entry(), "columns": np.zeros(7)}
    C.store(tmp_path, k, bad)
    assert C.load(tmp_path, k) is None
    assert "`columns` has shape (7,), expected (4,)" in capsys.readouterr().err


def test_a_corrupt_entry_is_reported_in_one_line(tmp_path, capsys):
    k = C.key({"d": 4})
    p = C.store(tmp_path, k, _entry())
    p.write_bytes(b"PK\x03\x04garbage")
    assert C.load(tmp_path, k) is None
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unreadable" in err[0]


def test_an_entry_with_nan_in_a_pass_is_reported_and_re_rendered(tmp_path, capsys):
    k = C.key({"e": 5})
    bad = _entry()
    bad["laser"][1, 2] = np.nan  # the sensor's Poisson noise fails on it ("lam value too large")
    C.store(tmp_path, k, bad)
    assert C.load(tmp_path, k) is None
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "`laser` holds NaN or infinity" in err[0] and "re-rendering" in err[0]
    C.store(tmp_path, k, _entry())
    assert C.load(tmp_path, k) is not None  # the re-render replaces it: not stuck


def test_an_entry_edited_on_disk_fails_its_checksum(tmp_path, capsys):
    k = C.key({"f": 6})
    p = C.store(tmp_path, k, _entry())
    with np.load(p) as z:
        arrays = {n: z[n] for n in z.files}
    arrays["columns"] = arrays["columns"] + 3.0  # the truth shifted 3 px, key and old checksum kept
    np.savez(p, **arrays)
    assert C.load(tmp_path, k) is None
    assert "checksum does not match" in capsys.readouterr().err


def test_an_entry_from_before_checksums_is_read_unverified(tmp_path):
    k = C.key({"g": 7})
    p = C._path(tmp_path, k)
    p.parent.mkdir(parents=True)
    np.savez(p, **_entry(), __key__=np.array(k))  # what CODE_VERSION 1 stored before checksums
    back = C.load(tmp_path, k)
    assert back is not None and set(back) == set(_entry())


def test_a_directory_in_an_entrys_place_is_removed_with_one_line(tmp_path, capsys):
    k = C.key({"h": 8})
    p = C._path(tmp_path, k)
    (p / "x").mkdir(parents=True)
    assert C.load(tmp_path, k) is None and not p.exists()
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is a directory, not a file: removed" in err[0]
    p.mkdir()
    C.store(tmp_path, k, _entry())  # store clears it too (a render that did not load first)
    assert C.load(tmp_path, k) is not None


def test_a_full_disk_while_storing_names_the_entry(tmp_path, monkeypatch):
    import errno

    def full(*a, **kw):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(np, "savez", full)
    k = C.key({"i": 9})
    with pytest.raises(OSError) as exc:
        C.store(tmp_path, k, _entry())
    assert exc.value.filename == str(C._path(tmp_path, k)) and exc.value.errno == errno.ENOSPC
    assert os.listdir(C._path(tmp_path, k).parent) == []


def test_three_ambient_bands_are_a_valid_entry(tmp_path, capsys):
    good = {"laser": np.zeros((4, 5), np.float32), "ambient": np.zeros((4, 5, 3), np.float32),
            "columns": np.zeros(4), "points_cm": np.zeros((4, 3)), "on_object": np.zeros(4, bool)}
    C.store(tmp_path, "k1", good)
    assert C.load(tmp_path, "k1")["ambient"].shape == (4, 5, 3)
    C.store(tmp_path, "k2", {**good, "ambient": np.zeros((4, 5, 2), np.float32)})
    assert C.load(tmp_path, "k2") is None and "`ambient` has shape (4, 5, 2)" in capsys.readouterr().err
