"""The ``auto`` sample counts: the table's lookups, the scene's passes and keys, and the renders."""

from pathlib import Path

import numpy as np
import pytest

import scenes
from scenes import cache as C, description, sampling

TINY = dict(width=64, height=60, cache=False)


@pytest.fixture
def table(monkeypatch):
    """Replace the generated table by the given entries for one test."""

    def put(kind, laser, ambient):
        monkeypatch.setattr(sampling, "LASER_KIND", kind)
        monkeypatch.setattr(sampling, "LASER_SPP", laser)
        monkeypatch.setattr(sampling, "AMBIENT_SPP", ambient)

    return put


def test_the_generated_block_is_well_formed_and_covers_only_known_materials():
    text = Path(sampling.__file__).read_text()
    assert text.count("# --- generated: begin ---\n") == 1 and text.count("# --- generated: end ---\n") == 1
    assert set(sampling.LASER_SPP) == set(sampling.LASER_KIND) <= set(scenes.MATERIALS)
    assert set(sampling.AMBIENT_SPP) <= set(scenes.MATERIALS)
    for m, kind in sampling.LASER_KIND.items():
        n_passes = {"path": 1, "ptracer": 1, "hybrid": 2, "split": 2, "split_hybrid": 3}[kind]
        assert len(sampling.LASER_SPP[m]) == n_passes, m
        assert all(isinstance(n, int) and n >= 1 for n in sampling.LASER_SPP[m]), m
        assert not scenes.materials.is_translucent(m)
    split = {m for m, kind in sampling.LASER_KIND.items() if kind in ("split", "split_hybrid")}
    assert set(sampling.OBJECT_SPP) <= split and set(sampling.MEASURED_OBJECT) <= split
    for m, per_object in sampling.OBJECT_SPP.items():
        for key, n in per_object.items():
            assert key.count("/") == 1 and isinstance(n, int) and n >= 1, (m, key)
            assert sampling.MEASURED_OBJECT[m][key]["spp"] == n and sampling.MEASURED_OBJECT[m][key]["certified"]
    for m, per_object in sampling.MEASURED_OBJECT.items():
        for key, rec in per_object.items():  # an uncertified object renders with the table's count
            assert rec["certified"] or rec["spp"] == sampling.LASER_SPP[m][0], (m, key)


def test_a_shiny_objects_own_count_applies_to_its_object_and_geometry_only(table, monkeypatch):
    table({"polished": "split_hybrid"}, {"polished": (16, 2, 2)}, {"polished": 2})
    monkeypatch.setattr(sampling, "OBJECT_SPP", {"polished": {sampling.case_key("cone", "none", "table"): 4}})
    assert sampling.object_spp("polished", "cone/none-table") == 4
    assert sampling.object_spp("polished", "cone/wall-table") is None and sampling.object_spp("glazed", "x") is None

    def counts(obj, **geometry):
        s = scenes.make(obj, material="polished", spp="auto", ambient_spp="auto", **geometry, **TINY)
        return s.sample_counts()[1], s

    on_table, cone = counts("cone", background="none", support="table")
    assert on_table == (4, 2, 2)
    assert counts("cone", background="wall", support="table")[0] == (16, 2, 2)
    assert counts("hand", background="none", support="table")[0] == (16, 2, 2)
    assert cone.sample_counts(8)[1] == (8, 8)  # an integer spp: the own passes (the split), each at it
    fixed = C.key(cone._cache_fields(0.1, "auto", 0, "v"))
    monkeypatch.setattr(sampling, "OBJECT_SPP", {})
    assert C.key(cone._cache_fields(0.1, "auto", 0, "v")) != fixed


def test_lookups_fall_back_to_the_fixed_counts(table):
    table({"matte": "ptracer"}, {"matte": (4,)}, {"matte": 2})
    assert sampling.laser_choice("matte") == ("ptracer", (4,)) and sampling.ambient_spp("matte") == 2
    assert sampling.laser_choice("glossy") is None
    assert sampling.ambient_spp("glossy") == sampling.FIXED_AMBIENT_SPP


def test_scene_passes_follow_the_table(table):
    table({"matte": "ptracer", "polished": "split"}, {"matte": (4,), "polished": (8, 2)},
          {"matte": 2, "polished": 3})
    passes, counts, amb = scenes.make("cone", material="matte", spp="auto", ambient_spp="auto", **TINY).sample_counts()
    assert [tuple(p) for p in passes] == [("ptracer", description.MAX_DEPTH, "all")] and counts == (4,) and amb == 2
    passes, counts, amb = scenes.make("cone", material="polished", spp="auto", ambient_spp="auto",
                                      **TINY).sample_counts()
    assert passes == description.laser_passes("polished") and counts == (8, 2) and amb == 3
    # an integer spp keeps the material's own passes at that count, whatever the table says
    passes, counts, amb = scenes.make("cone", material="matte", spp=5, ambient_spp=7, **TINY).sample_counts()
    assert passes == description.laser_passes("matte") and counts == (5,) and amb == 7
    # a polished table's passes are not the material's own: fixed counts
    s = scenes.make("cone", material="matte", spp="auto", support="table", support_finish="polished", **TINY)
    passes, counts, _ = s.sample_counts()
    assert [p.kind for p in passes] == ["path", "ptracer"] and counts == (sampling.FIXED_SPP,) * 2


def test_auto_shares_the_keys_of_the_same_fixed_counts(table):
    table({"matte": "path"}, {"matte": (16,)}, {"matte": 8})
    auto = scenes.make("cone", material="matte", spp="auto", ambient_spp="auto", **TINY)
    fixed = scenes.make("cone", material="matte", **TINY)
    assert C.key(auto._cache_fields(0.1, "auto", 0, "v")) == C.key(fixed._cache_fields(0.1, 16, 0, "v"))
    table({"matte": "path"}, {"matte": (4,)}, {"matte": 8})
    assert C.key(auto._cache_fields(0.1, "auto", 0, "v")) == C.key(fixed._cache_fields(0.1, 4, 0, "v"))
    table({"matte": "path"}, {"matte": (4,)}, {"matte": 2})
    assert C.key(auto._cache_fields(0.1, "auto", 0, "v")) != C.key(fixed._cache_fields(0.1, 4, 0, "v"))
    table({"matte": "ptracer"}, {"matte": (4,)}, {"matte": 8})
    fields = auto._cache_fields(0.1, "auto", 0, "v")
    assert fields["laser_passes"] == [["ptracer", description.MAX_DEPTH, "all"]]


def test_bad_counts_name_the_parameter():
    with pytest.raises(ValueError, match=r"`spp` must be an integer >= 1 or 'auto'"):
        scenes.make("cone", spp="AUTO", **TINY)
    s = scenes.make("cone", **TINY)
    with pytest.raises(ValueError, match=r"`spp` must be an integer >= 1, got 0"):
        s.sample_counts(0)


@pytest.mark.slow
def test_auto_renders_what_the_same_fixed_counts_render(table):
    table({"matte": "path"}, {"matte": (2,)}, {"matte": 1})
    auto = scenes.make("sphere", material="matte", spp="auto", ambient_spp="auto", **TINY).render(0.3)
    fixed = scenes.make("sphere", material="matte", spp=2, ambient_spp=1, **TINY).render(0.3)
    assert np.array_equal(auto.laser_radiance, fixed.laser_radiance) and np.array_equal(auto.radiance, fixed.radiance)
    assert np.array_equal(auto.image, fixed.image) and np.array_equal(auto.background, fixed.background)
    other = scenes.make("sphere", material="matte", spp=4, ambient_spp=1, **TINY).render(0.3)
    assert not np.array_equal(auto.laser_radiance, other.laser_radiance)


@pytest.mark.slow
def test_a_light_traced_choice_renders_with_the_light_tracer(table):
    table({"matte": "ptracer"}, {"matte": (2,)}, {"matte": 1})
    s = scenes.make("sphere", material="matte", spp="auto", ambient_spp="auto", **TINY)
    laser = s.render(0.3).laser_radiance
    loaded = s._load()[0]
    seeds = np.random.SeedSequence([0, *scenes.scene._angle_words(0.3)]).spawn(4)
    direct = loaded.render(description.pose_updates(s.rig, 0.3), 2, int(seeds[0].generate_state(1)[0]),
                           integrator=("ptracer", description.MAX_DEPTH))
    assert np.array_equal(laser, (direct.astype(np.float64) * s.laser_power_inband_w()).astype(np.float32))


@pytest.mark.slow
def test_the_light_traced_interreflections_are_the_path_tracers_bounce_light():
    # ptracer(3) - ptracer(2) with one seed: the light paths with a bounce (never negative beyond
    # float32 rounding); its mean over seeds matches path(3) - path(2), the same light by camera paths
    s = scenes.make("hand", material="matte", background="none", support="table", **TINY)
    loaded = s._load()[0]
    pose = description.pose_updates(s.rig, 0.0)
    indirect = np.mean([loaded.render(pose, 8, seed, integrator=("light_indirect", 3)) for seed in range(4)], axis=0)
    first = loaded.render(pose, 8, 0, integrator=("ptracer", 3))
    assert indirect.min() >= -1e-6 * first.max()
    by_path = np.mean([loaded.render(pose, 64, 10 + seed, integrator=("path", 3))
                       - loaded.render(pose, 64, 10 + seed, integrator=("path", 2)) for seed in range(2)], axis=0)
    assert by_path.sum() > 0
    assert abs(indirect.sum() / by_path.sum() - 1.0) < 0.1
    # and it is a small part of the whole laser light
    assert indirect.sum() < 0.5 * first.sum()


@pytest.mark.slow
def test_a_hybrid_choice_sums_its_two_passes(table):
    table({"matte": "hybrid"}, {"matte": (2, 1)}, {"matte": 1})
    s = scenes.make("sphere", material="matte", spp="auto", ambient_spp="auto", **TINY)
    assert s.laser_passes() == description.hybrid_passes()
    laser = s.render(0.3).laser_radiance
    loaded = s._load()[0]
    seed = int(np.random.SeedSequence([0, *scenes.scene._angle_words(0.3)]).spawn(4)[0].generate_state(1)[0])
    pose = description.pose_updates(s.rig, 0.3)
    parts = (loaded.render(pose, 2, seed, integrator=("path", 2), pixels=s.lit_pixels(0.3)).astype(np.float64)
             + loaded.render(pose, 1, seed, integrator=("light_indirect", 3)))
    assert np.array_equal(laser, (parts.astype(np.float32).astype(np.float64) * s.laser_power_inband_w())
                          .astype(np.float32))
    assert "laser_passes" in s._cache_fields(0.3, "auto", 0, "v")
