import pytest

from bench.config import PROFILES, Config, ConfigError, load, parse, profile, with_overrides

GOOD = {
    "name": "t",
    "seed": 3,
    "trackers": ["threshold", "dp4"],
    "baselines": ["threshold"],
    "dp": ["dp4"],
    "n_samples": 10,
    "n_boot": 50,
    "render": {"width": 64, "height": 60, "spp": 2},
    "experiments": [{"scene": "cone", "material": "patchy", "n_angles": 3, "ambient_lux": 200.0}],
}


def test_profiles_parse_and_round_trip():
    for name in PROFILES:
        cfg = profile(name)
        assert isinstance(cfg, Config) and cfg.name == name
        assert parse(cfg.to_dict()).to_dict() == cfg.to_dict()


def test_paper_profile_is_the_papers_condition():
    cfg = profile("paper")
    assert cfg.render["width"] == 512 and cfg.render["height"] == 480 and cfg.n_samples == 150
    assert {(e.scene, e.material) for e in cfg.experiments} >= {("cone", "patchy"), ("hand", "patchy")}
    assert {e.material for e in cfg.experiments} >= {"patchy", "absorbing", "glossy", "specular"}


def test_good_config_and_experiment_key():
    cfg = parse(GOOD)
    assert cfg.trackers == ("threshold", "dp4") and cfg.experiments[0].overrides == {"ambient_lux": 200.0}
    assert cfg.experiments[0].key == "cone-patchy_ambient_lux=200.0"


def test_empty_tracker_list_means_all_registered():
    import trackers

    cfg = parse({**GOOD, "trackers": [], "baselines": [], "dp": []})
    assert list(cfg.trackers) == trackers.available()


@pytest.mark.parametrize(
    "change, message",
    [
        ({"colour": 1}, r"unknown key `colour`"),
        ({"seed": -1}, r"`seed` must be an integer >= 0, got -1"),
        ({"seed": 1.5}, r"`seed` must be an integer >= 0, got 1.5"),
        ({"trackers": ["nope"]}, r"`trackers` names unknown tracker 'nope'"),
        ({"trackers": "dp4"}, r"`trackers` must be a list of names, got 'dp4'"),
        ({"dp": ["dp8"]}, r"`dp` names 'dp8', which is not among `trackers`"),
        ({"n_samples": 0}, r"`n_samples` must be an integer >= 1, got 0"),
        ({"render": {"width": 64, "height": 60, "spp": 0}}, r"`render.spp` must be an integer >= 1, got 0"),
        ({"render": {"dpi": 3}}, r"unknown key `render.dpi`"),
        ({"experiments": []}, r"`experiments` must be a non-empty list"),
        ({"experiments": [{"scene": "teapot"}]}, r"`experiments\[0\].scene` must be one of .*, got 'teapot'"),
        ({"experiments": [{"scene": "cone", "material": "velvet"}]}, r"`experiments\[0\].material` must be one of"),
        ({"experiments": [{"scene": "cone", "n_angles": 1}]}, r"`experiments\[0\].n_angles` must be an integer >= 2"),
        ({"experiments": [{"scene": "cone", "angles": [1, "a"]}]}, r"`experiments\[0\].angles` must be a list"),
        ({"experiments": [{"scene": "cone", "angles": [1, 2], "n_angles": 3}]}, r"gives both"),
        ({"experiments": [{"scene": "cone", "laser_power_mw": -3}]}, r"`experiments\[0\]`: .*laser_power_mw.*-3"),
        ({"experiments": [{"scene": "cone", "wobble": 1}]}, r"unknown key `experiments\[0\].wobble`"),
        ({"experiments": [{"scene": "cone"}, {"scene": "cone"}]}, r"lists 'cone-matte' twice"),
        ({"render": {"width": 100, "height": 60}}, r"`experiments\[0\]`: .*square pixels"),
    ],
)
def test_bad_configs_name_the_key_and_value(change, message):
    with pytest.raises(ConfigError, match=message):
        parse({**GOOD, **change})


def test_load_errors(tmp_path):
    with pytest.raises(ConfigError, match="cannot read configuration"):
        load(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("name = [unclosed")
    with pytest.raises(ConfigError, match="invalid TOML"):
        load(bad)
    good = tmp_path / "good.toml"
    good.write_text('name = "x"\n[[experiments]]\nscene = "plane"\nmaterial = "matte"\nn_angles = 2\n')
    assert load(good).source == str(good)
    with pytest.raises(ConfigError, match="unknown profile 'fast'"):
        profile("fast")


def test_with_overrides_revalidates():
    cfg = parse(GOOD)
    assert with_overrides(cfg, seed=9).seed == 9
    with pytest.raises(ConfigError, match="`seed` must be"):
        with_overrides(cfg, seed=-2)
