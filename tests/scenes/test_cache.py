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
