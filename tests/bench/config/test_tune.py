"""The tuning profile's schema (bench/config/tune.py): ConfigError, the run's limits."""

import pytest

from bench.config import RENDER_KEYS, ConfigError
from bench.config.tune import DEFAULT_PROFILE, TUNE_RENDER_KEYS, load_profile, parse_profile
from bench.store.textfiles import loads_toml
from bench.studies.hard_frames import KINDS


def _profile(**changes):
    doc = loads_toml(DEFAULT_PROFILE.read_text(), "p")
    doc["experiments"] = doc["experiments"][:1]
    for k, v in changes.items():
        doc[k] = v
    return doc


def test_the_committed_profile_is_valid():
    p = load_profile(DEFAULT_PROFILE, KINDS)
    assert p.seed != 0 and p.render["n_angles"] >= 2


def test_the_render_table_is_the_runs_without_ambient_spp():
    assert set(TUNE_RENDER_KEYS) == (set(RENDER_KEYS) - {"ambient_spp"}) | {"n_angles"}


@pytest.mark.parametrize("changes, message", [
    ({"render": {"width": 64, "height": 60, "spp": 10**9, "n_angles": 2}}, r"`render.spp` must be an integer 1 \.\."),
    ({"experiments": [{"scene": "teapot", "material": "matte"}]}, r"`experiments\[0\].scene` must be one of"),
    ({"experiments": [{"scene": "plane", "material": "matte", "ambient_lux": 1e9}]},
     r"`experiments\[0\].ambient_lux` must be at most"),
    ({"experiments": [{"scene": "plane", "material": "matte", "albedo": 1}]}, r"unknown key `experiments\[0\].albedo`"),
    ({"tie": float("nan")}, "`tie` must be a finite number >= 0"),
    ({"name": ""}, "`name` must be a non-empty string"),
])
def test_bad_values_raise_config_error_naming_the_key(changes, message):
    with pytest.raises(ConfigError, match=message):
        parse_profile(_profile(**changes), KINDS)


def test_an_unreadable_profile_is_a_config_error(tmp_path):
    (tmp_path / "p.toml").write_bytes(b"name = '\xff'")
    with pytest.raises(ConfigError, match="tuning profile .* is not UTF-8 text"):
        load_profile(tmp_path / "p.toml")
