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
        ({"trackers": ["nope"]}, r"`trackers\[0\]` names unknown tracker 'nope'"),
        ({"trackers": "dp4"}, r"`trackers` must be a list of tracker names or settings, got 'dp4'"),
        ({"trackers": ["dp4", "dp4"]}, r"`trackers` repeats the label 'dp4'"),
        ({"trackers": ["dp4", {"name": "dp4", "params": {"eps": 2.0}}]}, r"repeats the label 'dp4'"),
        ({"trackers": [{"label": "x", "name": "dp4", "params": {"wobble": 1}}]},
         r"`trackers\[0\].params` has an unknown parameter of 'dp4' among \['wobble'\]; valid: eps"),
        ({"trackers": [{"label": "x", "name": "dp4", "params": {"eps": -1}}]}, r"`trackers\[0\].params`: .*eps.*-1"),
        ({"trackers": [{"label": "a b", "name": "dp4"}]}, r"`trackers\[0\].label` must be letters"),
        ({"trackers": [{"label": "x", "name": "dp4", "colour": 1}]}, r"unknown key `trackers\[0\].colour`"),
        ({"trackers": [3]}, r"`trackers\[0\]` must be a tracker name or a table"),
        ({"dp": ["dp8"]}, r"`dp` names 'dp8', which is not among `trackers`"),
        ({"n_samples": 0}, r"`n_samples` must be an integer >= 1, got 0"),
        ({"render": {"width": 64, "height": 60, "spp": 0}}, r"`render.spp` must be an integer >= 1 or \"auto\", got 0"),
        ({"render": {"width": 64, "height": 60, "spp": "many"}}, r"`render.spp` must be an integer >= 1 or \"auto\", got .many."),
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
        ({"render_ahead": "no"}, r"`render_ahead` must be true or false, got 'no'"),
        ({"render_ahead": 0}, r"`render_ahead` must be true or false, got 0"),
        ({"llvm_target": 8}, r"`llvm_target` must be a string, got 8"),
        ({"llvm_target": "haswell/6"}, r"`llvm_target` must be \"\", \"portable\", \"native\" or CPU/WIDTH"),
    ],
)
def test_bad_configs_name_the_key_and_value(change, message):
    with pytest.raises(ConfigError, match=message):
        parse({**GOOD, **change})


def test_tracker_settings_compare_two_settings_of_one_tracker():
    cfg = parse({**GOOD, "trackers": ["threshold", "dp4", {"label": "dp4_e2", "name": "dp4", "params": {"eps": 2.0}}],
                 "dp": ["dp4", "dp4_e2"]})
    assert cfg.trackers == ("threshold", "dp4", "dp4_e2") and cfg.dp == ("dp4", "dp4_e2")
    made = cfg.make_trackers()
    assert list(made) == ["threshold", "dp4", "dp4_e2"]
    assert made["dp4"].get_params()["eps"] == 1.0 and made["dp4_e2"].get_params()["eps"] == 2.0
    again = parse(cfg.to_dict())
    assert again.tracker_specs == cfg.tracker_specs and again.to_dict() == cfg.to_dict()
    assert cfg.to_dict()["trackers"][:2] == ["threshold", "dp4"]  # plain settings stay plain names


def test_tracker_settings_on_the_command_line():
    from bench.config import parse_trackers_arg

    specs = parse_trackers_arg('threshold, {label = "dp4_e2", name = "dp4", params = {eps = 2.0}}, dp8')
    assert [(s.label, s.name, s.params) for s in specs] == [
        ("threshold", "threshold", {}), ("dp4_e2", "dp4", {"eps": 2.0}), ("dp8", "dp8", {})]
    with pytest.raises(ConfigError, match=r"--trackers: .* is not a TOML inline table"):
        parse_trackers_arg("{label = }")
    with pytest.raises(ConfigError, match=r"--trackers must name at least one tracker"):
        parse_trackers_arg(" , ")
    with pytest.raises(ConfigError, match=r"`--trackers\[1\]` names unknown tracker 'nope'"):
        parse_trackers_arg("dp4,nope")


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


def test_background_and_support_are_experiment_overrides():
    e = {"scene": "cone", "material": "patchy", "n_angles": 3, "background": "none", "support": "table",
         "support_albedo": 0.3}
    cfg = parse({**GOOD, "experiments": [e]})
    assert cfg.experiments[0].overrides == {"background": "none", "support": "table", "support_albedo": 0.3}
    with pytest.raises(ConfigError, match=r"`experiments\[0\]`: `support` must be one of 'none', 'table', got 'box'"):
        parse({**GOOD, "experiments": [{**e, "support": "box"}]})
    with pytest.raises(ConfigError, match=r"`experiments\[0\]`: `background_distance_cm` must put the wall behind"):
        parse({**GOOD, "experiments": [{**e, "background": "wall", "background_distance_cm": 30.0}]})


def test_the_documented_example_configuration_is_valid():
    import pathlib
    import re
    import tomllib

    from bench.config import parse

    doc = (pathlib.Path(__file__).resolve().parents[3] / "docs" / "config.md").read_text()
    block = re.search(r"```toml\n(.*?)```", doc, re.S).group(1)
    cfg = parse(tomllib.loads(block))
    assert cfg.trackers == ("threshold", "centroid", "dp4", "dp8_eps2") and len(cfg.experiments) == 2
    assert cfg.experiments[1].overrides == {"ambient_lux": 200.0, "laser_power_mw": 5.0}


def test_schema_has_one_home():
    from dataclasses import fields

    from bench import config
    from bench.config import schema
    from scenes.params import DEFAULTS

    assert schema._TOP == {f.name for f in fields(config.Config)} - {"source", "tracker_specs"}
    assert set(config.scene_override_keys()) == set(DEFAULTS) - set(config.HARNESS_KEYS)
    assert config.parse({"experiments": [{"scene": "plane"}]}).n_samples == config.Config.n_samples


def test_render_ahead_round_trips_but_is_not_part_of_the_runs_identity():
    from bench.store.runfolder import default_run_dir

    on, off = parse(GOOD), parse({**GOOD, "render_ahead": False})
    assert on.render_ahead is True and off.render_ahead is False
    assert "render_ahead" not in on.to_dict()  # a default configuration's dict (and run folder) as before
    assert parse(off.to_dict()).render_ahead is False and off.to_dict()["render_ahead"] is False
    assert on.identity() == off.identity() and default_run_dir(on) == default_run_dir(off)
    assert with_overrides(on, render_ahead=False).render_ahead is False


# -- a tracker setting's own `restore` ---------------------------------------------------------

GAPS = {"label": "threshold_gaps", "name": "threshold", "restore": "none"}


def test_a_setting_carries_its_own_restore_over_the_runs():
    cfg = parse({**GOOD, "trackers": ["threshold", "dp4", GAPS], "baselines": ["threshold", "threshold_gaps"]})
    spec = cfg.tracker_specs[2]
    assert (spec.label, spec.name, spec.params, spec.restore) == ("threshold_gaps", "threshold", {}, "none")
    assert cfg.restore_by_label() == {"threshold": "rows", "dp4": "rows", "threshold_gaps": "none"}
    assert cfg.to_dict()["trackers"] == ["threshold", "dp4", {**GAPS, "params": {}}]
    again = parse(cfg.to_dict())
    assert again.tracker_specs == cfg.tracker_specs and again.to_dict() == cfg.to_dict()
    # the run's own restore applies to every setting without one; the setting's wins over it
    none_run = parse({**GOOD, "restore": "none", "trackers": ["threshold", {**GAPS, "restore": "rows"}], "dp": []})
    assert none_run.restore_by_label() == {"threshold": "none", "threshold_gaps": "rows"}
    # a setting without its own restore is written as before (its run folder's name does not change)
    assert parse(GOOD).to_dict()["trackers"] == ["threshold", "dp4"]


def test_a_settings_restore_is_part_of_the_runs_identity():
    from bench.store.runfolder import default_run_dir

    gaps = parse({**GOOD, "trackers": ["threshold", "dp4", GAPS]})
    rows = parse({**GOOD, "trackers": ["threshold", "dp4", {**GAPS, "restore": "rows"}]})
    plain = parse({**GOOD, "trackers": ["threshold", "dp4", {k: v for k, v in GAPS.items() if k != "restore"}]})
    assert gaps.identity() != rows.identity() != plain.identity() != gaps.identity()
    assert len({default_run_dir(c) for c in (gaps, rows, plain)}) == 3


@pytest.mark.parametrize(
    "setting, message",
    [
        ({**GAPS, "restore": "fill"}, r"^`trackers\[2\].restore` must be one of 'rows', 'none', got 'fill'$"),
        ({**GAPS, "restore": 1}, r"^`trackers\[2\].restore` must be one of 'rows', 'none', got 1$"),
        ({**GAPS, "name": "nope"}, r"^`trackers\[2\]` names unknown tracker 'nope'; available: "),
        ({**GAPS, "fill": "none"}, r"^unknown key `trackers\[2\].fill` \(valid: label, name, params, restore, "
                                     r"timeout_s, isolate\)$"),
    ],
)
def test_a_bad_setting_restore_is_one_line(setting, message):
    with pytest.raises(ConfigError, match=message) as err:
        parse({**GOOD, "trackers": ["threshold", "dp4", setting]})
    assert "\n" not in str(err.value)


def test_a_setting_restore_on_the_command_line():
    from bench.config import parse_trackers_arg

    specs = parse_trackers_arg('threshold, {label = "g", name = "threshold", restore = "none"}')
    assert [(s.label, s.restore) for s in specs] == [("threshold", None), ("g", "none")]
    with pytest.raises(ConfigError, match=r"`--trackers\[1\].restore` must be one of 'rows', 'none', got 'x'"):
        parse_trackers_arg('threshold, {label = "g", name = "threshold", restore = "x"}')


def test_the_paper_profile_reads_without_dp_three_ways():
    from bench.evaluate.readings import PAPER_READING, reading_of

    cfg = profile("paper")
    values = {s.label: s.to_value() for s in cfg.tracker_specs}
    kinds = {lab: reading_of(v, cfg.restore) for lab, v in values.items()}
    assert {lab: k for lab, k in kinds.items() if k} == {"threshold": "filled", "threshold_gaps": "gaps",
                                                         "argmax": "argmax"}
    assert PAPER_READING in kinds.values()
    assert set(cfg.baselines) >= {"threshold", "threshold_gaps", "argmax"} and cfg.baselines[0] == "threshold"
    assert cfg.restore_by_label()["threshold_gaps"] == "none" and cfg.restore == "rows"
    # argmax reports a brightest pixel in every row of an 8-bit frame (ties: the middle of the brightest run)
    import numpy as np

    rng = np.random.default_rng(0)
    img = rng.integers(0, 3, size=(40, 30)).astype(np.uint8)
    img[5] = 0  # an all-black row: one of its brightest pixels is still reported
    cols = cfg.make_trackers()["argmax"].track(img).columns
    assert not np.isnan(cols).any() and np.array_equal(cols, np.round(cols))
    assert (img[np.arange(40), cols.astype(int)] == img.max(axis=1)).all()


def test_none_in_a_trackers_params_is_none():
    import numpy as np

    import trackers
    from bench.config import parse_trackers_arg

    level_alone = ('{label = "lv", name = "dp8", params = {stripe_test = {width_ratio = "none", flank_level = "none", '
                   'colour_min = "none", off_ratio = "none", continuity_rows = "none", level_min = 0.15}}}')
    lv, wide = parse_trackers_arg(level_alone + ', {label = "w", name = "threshold", params = {width_ratio = "none"}}')
    assert lv.params["stripe_test"] == {"width_ratio": None, "flank_level": None, "colour_min": None,
                                        "off_ratio": None, "continuity_rows": None, "level_min": 0.15}
    assert wide.make().width_ratio is None and wide.to_value()["params"] == {"width_ratio": None}
    # the same tracker as one built with None: the same columns on a frame
    rng = np.random.default_rng(0)
    frame = rng.normal(20.0, 2.0, (40, 60))
    frame[:, 30] += 120.0
    frame[:10, 5] += 15.0  # a dim ridge in the top rows: the level test says no to it
    built = trackers.make("dp8", stripe_test={**{k: None for k in ("width_ratio", "flank_level", "colour_min",
                                                                 "off_ratio", "continuity_rows")}, "level_min": 0.15})
    np.testing.assert_array_equal(lv.make().track(frame).columns, built.track(frame).columns)
    # a parameter that cannot be None is still refused, naming it
    with pytest.raises(ConfigError, match="`k_sigma` must be"):
        parse_trackers_arg('{label = "x", name = "threshold", params = {k_sigma = "none"}}')
