import os

import numpy as np

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


def test_three_ambient_bands_are_a_valid_entry(tmp_path, capsys):
    good = {"laser": np.zeros((4, 5), np.float32), "ambient": np.zeros((4, 5, 3), np.float32),
            "columns": np.zeros(4), "points_cm": np.zeros((4, 3)), "on_object": np.zeros(4, bool)}
    C.store(tmp_path, "k1", good)
    assert C.load(tmp_path, "k1")["ambient"].shape == (4, 5, 3)
    C.store(tmp_path, "k2", {**good, "ambient": np.zeros((4, 5, 2), np.float32)})
    assert C.load(tmp_path, "k2") is None and "`ambient` has shape (4, 5, 2)" in capsys.readouterr().err
