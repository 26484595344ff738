"""Rendering through the public API at small sizes (Mitsuba; a few seconds)."""

import pickle

import numpy as np
from scipy import ndimage
import pytest

import scenes
from scenes import cache as C

pytestmark = pytest.mark.slow

SMALL = dict(width=128, height=120)


@pytest.fixture(scope="module")
def matte():
    return scenes.make("sphere", material="matte", cache=False, **SMALL)


def test_frame_contents(matte):
    f = matte.render(0.5)
    h, w = 120, 128
    assert f.image.shape == f.background.shape == (h, w) and f.image.dtype == f.background.dtype == np.uint8
    assert f.radiance.dtype == f.laser_radiance.dtype == np.float32 and f.radiance.shape == (h, w)
    assert f.truth.columns.shape == (h,) and f.truth.points_cm.shape == (h, 3) and f.truth.on_object.dtype == bool
    assert f.mirror_angle_deg == 0.5 and f.variant in ("llvm_ad_mono", "cuda_ad_mono", "scalar_rgb")
    assert np.all(f.radiance >= f.laser_radiance)
    assert f.truth.on_object.sum() > 60 and np.all(np.isnan(f.truth.columns[~f.truth.valid]))
    # the stripe is in the image where the truth says
    rows = np.nonzero(f.truth.on_object)[0]
    peak = np.argmax(f.laser_radiance[rows], axis=1)
    assert np.all(np.abs(peak - f.truth.columns[rows]) <= 1.0)


def test_frames_are_pure_functions_of_params_angle_and_seed(matte):
    a = matte.render(1.0, seed=3)
    matte.render(-2.0, seed=4)
    b = matte.render(1.0, seed=3)
    c = scenes.make("sphere", material="matte", cache=False, **SMALL).render(1.0, seed=3)
    for x in (b, c):
        assert np.array_equal(a.image, x.image) and np.array_equal(a.background, x.background)
        assert np.array_equal(a.radiance, x.radiance)
    d = matte.render(1.0, seed=5)
    assert not np.array_equal(a.image, d.image)
    assert not np.array_equal(a.background, matte.render(1.25, seed=3).background)


@pytest.mark.parametrize("material", ["specular", "polished"])
def test_light_traced_frames_are_reproducible(material):
    s = scenes.make("cone", material=material, cache=False, spp=4, **SMALL)
    a = s.render(2.3)
    s.render(0.0)
    b = s.render(2.3)
    if a.variant.startswith("cuda"):
        # ptracer's atomic splats on the GPU reproduce only to float32 rounding
        # (measured on an H100); the LLVM and scalar variants are bit-identical
        assert np.allclose(a.radiance, b.radiance, rtol=1e-5, atol=1e-12)
    else:
        assert np.array_equal(a.radiance, b.radiance)


def test_scene_pickles_without_mitsuba_objects(matte):
    matte.render(0.0)
    clone = pickle.loads(pickle.dumps(matte))
    assert clone._loaded is None and clone.params == matte.params
    assert np.array_equal(clone.render(0.0).image, matte.render(0.0).image)


def test_cache_reuses_renders_and_survives_corruption(tmp_path, monkeypatch):
    s = scenes.make("sphere", material="matte", cache_dir=str(tmp_path), **SMALL)
    a = s.render(0.25)
    files = list(tmp_path.rglob("*.npz"))
    assert len(files) == 1
    fresh = scenes.make("sphere", material="matte", cache_dir=str(tmp_path), laser_power_mw=6.0,
                        ambient_lux=0.0, exposure_ms=2.0, **SMALL)
    monkeypatch.setattr(scenes.Scene, "_load", lambda self, spp: pytest.fail("re-rendered"))
    b = fresh.render(0.25)  # power, lux and sensor changes reuse the unit renders
    assert np.allclose(b.laser_radiance, 2 * a.laser_radiance, rtol=1e-6)
    assert np.array_equal(b.radiance, b.laser_radiance) and b.background.max() <= 1
    monkeypatch.undo()
    files[0].write_bytes(b"not a zip file")
    c = s.render(0.25)
    assert np.array_equal(c.image, a.image)
    assert C.load(files[0].parent.parent, files[0].stem) is not None  # rewritten


def test_centroid_of_the_noiseless_stripe_matches_the_truth():
    """Matte plane, line widened to ~3 px at 128x120; the test's own centre of mass in a wide window."""
    s = scenes.make("plane", material="matte", cache=False, line_fwhm_mrad=12.0, **SMALL)
    errors = []
    for theta in (-2.0, 0.0, 2.0):
        f = s.render(theta)
        img = f.laser_radiance.astype(float)
        for r in np.nonzero(f.truth.valid)[0]:
            c = int(np.argmax(img[r]))
            lo, hi = max(0, c - 14), min(img.shape[1], c + 15)
            w = img[r, lo:hi]
            errors.append((w * np.arange(lo, hi)).sum() / w.sum() - f.truth.columns[r])
    errors = np.array(errors)
    assert len(errors) > 300
    assert np.sqrt(np.mean(errors ** 2)) < 0.05


def test_specular_cone_throws_a_false_stripe_on_the_backdrop():
    theta = 2.3  # the sheet grazes the cone's side and is reflected forward onto the wall
    energies = {}
    for material in ("matte", "specular"):
        s = scenes.make("cone", material=material, cache=False, **SMALL)
        f = s.render(theta)
        pts, on_object = s.visible_points(theta)
        _, n = s.rig.laser_plane(theta)
        near_object = on_object.copy()
        near_object[:, 1:] |= on_object[:, :-1]
        near_object[:, :-1] |= on_object[:, 1:]
        off_line_backdrop = ~near_object & (np.abs(pts @ n) > 0.5)  # > 5 mm from the true line
        energies[material] = float((f.laser_radiance * off_line_backdrop).sum())
    assert energies["specular"] > 10 * energies["matte"]
    assert energies["specular"] > 0.5


def test_patchy_material_hides_parts_of_the_stripe():
    theta = 0.0
    seen = {}
    for material in ("matte", "patchy"):
        s = scenes.make("sphere", material=material, cache=False, **SMALL)
        f = s.render(theta)
        rows = np.nonzero(f.truth.on_object)[0]
        seen[material] = f.laser_radiance[rows].max(axis=1)
    ratio = seen["patchy"] / seen["matte"]
    assert 0.15 < np.mean(ratio < 0.1) < 0.7  # rows crossing dark bands/patches (albedo 0.03 / 0.85)
    assert np.mean(ratio > 0.95) > 0.25  # the rest is the same white as matte


def test_default_levels_on_white_and_on_absorbing_at_full_size():
    """3 mW on a white object near 100 DN, 400 lux on it a few DN; 17x less on the absorbing one."""
    levels = {}
    for material in ("matte", "absorbing"):
        f = scenes.make("sphere", material=material, cache=False).render(0.0)
        on = f.truth.on_object
        peak = f.image[on].max(axis=1).astype(float)
        levels[material] = (np.median(peak), np.median(f.background[on]))
    assert 70 <= levels["matte"][0] <= 130 and 1 <= levels["matte"][1] <= 4
    assert levels["absorbing"][0] < 12 and levels["absorbing"][1] <= 1


def test_scan_and_default_angles(matte):
    angles = matte.default_angles()
    assert len(angles) == matte.params["n_angles"] and np.all(np.diff(angles) > 0)
    frames = list(matte.scan(angles[:2], progress=False))
    assert [f.mirror_angle_deg for f in frames] == list(angles[:2])


def test_bad_render_arguments(matte):
    with pytest.raises(ValueError, match="`spp` must be an integer >= 1, got 0"):
        matte.render(0.0, spp=0)
    with pytest.raises(ValueError, match="`mirror_angle_deg` must be a finite number, got nan"):
        matte.render(float("nan"))
    with pytest.raises(ValueError, match="`seed` must be an integer >= 0, got -2"):
        matte.render(0.0, seed=-2)


TINY = dict(width=64, height=60, spp=2, ambient_spp=1, cache=False)


@pytest.mark.parametrize("name,value", [("background", "none"), ("background_distance_cm", 80.0),
                                        ("background_albedo", 0.2), ("support", "table"),
                                        ("support_albedo", 0.3)])
def test_background_and_support_parameters_change_the_render_cache_key(name, value):
    def cache_key(**kw):
        s = scenes.make("cone", **kw)
        return C.key(s._cache_fields(0.0, 16, 0, "llvm_ad_mono"))

    assert cache_key(**{name: value}) != cache_key()
    assert cache_key(**{name: scenes.DEFAULTS[name]}) == cache_key()


def test_make_refuses_a_wall_in_front_of_the_object():
    with pytest.raises(ValueError, match=r"`background_distance_cm` must put the wall behind the hand"):
        scenes.make("hand", background_distance_cm=30.0)


def test_no_background_means_no_truth_on_the_background():
    s = scenes.make("sphere", background="none", **TINY)
    wall = scenes.make("sphere", **TINY)
    for theta in (s.default_angles()[0], 0.0):
        f, g = s.render(theta), wall.render(theta)
        assert not np.any(f.truth.part == 0) and np.array_equal(f.truth.valid, f.truth.part == 1)
        assert np.any(g.truth.part == 0)  # the same frame with today's wall has truth on it
        assert np.all(np.isnan(f.truth.columns[~f.truth.on_object]))
    assert not s.render(s.default_angles()[0]).truth.valid.any()  # the sheet misses the sphere: no truth


@pytest.mark.parametrize("background", ["wall", "none"])
def test_table_carries_the_truth_below_the_object(background):
    s = scenes.make("cone", support="table", background=background, **TINY)
    f = s.render(0.0)
    t = f.truth
    on, table = np.nonzero(t.part == 1)[0], np.nonzero(t.part == 2)[0]
    assert len(on) > 40 and len(table) > 0
    assert table.min() > on.max() and table.max() == 59  # below the object, down to the last row
    assert not t.on_object[table].any() and np.all(np.isfinite(t.columns[table]))
    top = s.object.mesh.vertices_cm[:, 2].min()
    assert np.allclose(t.points_cm[table, 2], top, atol=1e-4)  # on the table's top
    assert np.all(f.laser_radiance[table, np.round(t.columns[table]).astype(int)] > 0)  # lit by the sheet
    # the object's own truth is the same as without the table
    plain = scenes.make("cone", background=background, **TINY).render(0.0).truth
    both = (plain.part == 1) & (t.part == 1)
    assert both.sum() >= len(on) - 1 and np.allclose(t.columns[both], plain.columns[both], atol=1e-4)


def test_wall_distance_moves_the_wall_truth_as_equation_3_predicts():
    rig = scenes.make("sphere", **TINY).rig
    cols = {}
    for d in (50.0, 60.0, 80.0):
        s = scenes.make("sphere", background_distance_cm=d, **TINY)
        theta = float(s.default_angles()[0])  # the sheet misses the sphere: the wall only
        t = s.render(theta).truth
        wall = t.part == 0
        if d < rig.imaged_range_cm(edges=True)[1]:
            assert wall.sum() == 60
            r_lit = d / np.cos(np.radians(2.0 * theta))  # the sheet meets the wall this far from the axis
            assert np.allclose(rig.depth_of_column_cm(t.columns[wall]), r_lit, rtol=1e-5)
            cols[d] = np.nanmean(t.columns)
        else:  # beyond R_max: the wall's stripe is out of the image
            assert not t.valid.any()
    assert cols[60.0] < cols[50.0] - 5  # farther is further left


def test_noise_draws_share_the_render_and_differ_in_sensor_noise(matte):
    a = matte.render(1.0, seed=3)
    a0 = matte.render(1.0, seed=3, noise_draw=0)
    b = matte.render(1.0, seed=3, noise_draw=1)
    b_again = matte.render(1.0, seed=3, noise_draw=1)
    c = matte.render(1.0, seed=3, noise_draw=2)
    assert np.array_equal(a.image, a0.image) and np.array_equal(a.background, a0.background)
    assert np.array_equal(a.radiance, b.radiance) and np.array_equal(b.radiance, c.radiance)
    assert np.array_equal(b.image, b_again.image) and np.array_equal(b.background, b_again.background)
    for x, y in ((a, b), (b, c), (a, c)):
        assert not np.array_equal(x.image, y.image) and not np.array_equal(x.background, y.background)
    with pytest.raises(ValueError, match="`noise_draw` must be an integer >= 0, got -1"):
        matte.render(1.0, noise_draw=-1)


def _dilate(mask, k):
    plus = np.zeros((2 * k + 1, 2 * k + 1), bool)  # grown by up to k px along rows and columns
    plus[k, :] = plus[:, k] = True
    return ndimage.binary_dilation(mask, structure=plus)


@pytest.fixture(scope="module")
def shiny_cone_frames():
    """Cone at 2.3 deg (the sheet grazes its side and is mirrored forward onto the wall)."""
    theta = 2.3
    out = {}
    for material in ("matte", "polished", "glazed"):
        s = scenes.make("cone", material=material, cache=False, **SMALL)
        pts, on_object = s.visible_points(theta)
        out[material] = (s, s.render(theta), pts, on_object)
    return theta, out


@pytest.mark.parametrize("material", ["polished", "glazed"])
def test_shiny_object_shows_its_true_stripe(material):
    """Sphere facing the rig: a highlight that saturates (polished) or a diffuse stripe (glazed)."""
    theta = 0.0
    s = scenes.make("sphere", material=material, cache=False, **SMALL)
    f = s.render(theta)
    _, on_object = s.visible_points(theta)
    rows = np.nonzero(f.truth.on_object)[0]
    assert len(rows) > 80
    img = f.laser_radiance.astype(float)
    errors = []
    for r in rows:
        on_row = np.where(on_object[r], img[r], 0.0)  # centroid around the brightest object pixel
        c = int(np.argmax(on_row))
        lo, hi = max(0, c - 3), min(img.shape[1], c + 4)
        w = on_row[lo:hi]
        errors.append((w * np.arange(lo, hi)).sum() / w.sum() - f.truth.columns[r])
    assert np.mean(np.abs(np.array(errors)) < 1.0) > 0.8
    excess_dn = f.image[rows].max(axis=1).astype(float) - f.background[rows].max(axis=1)
    if material == "polished":  # a narrow highlight: saturated in a few rows, visible in a third of them
        assert f.image[rows].max() == 255 and 0.3 < np.mean(excess_dn >= 5) < 0.9
    else:
        assert np.mean(excess_dn >= 20) > 0.8


@pytest.mark.parametrize("material", ["polished", "glazed"])
def test_shiny_object_throws_a_false_stripe_where_the_mask_says(shiny_cone_frames, material):
    theta, frames = shiny_cone_frames
    s, f, pts, on_object = frames[material]
    _, n = s.rig.laser_plane(theta)
    off_line = ~_dilate(on_object, 1) & np.isfinite(pts[..., 0]) & (np.abs(pts @ n) > 0.5)
    energy = {m: float((frames[m][1].laser_radiance * off_line).sum()) for m in ("matte", material)}
    assert energy[material] > 5 * energy["matte"]  # matte: diffuse interreflection only
    mask = f.truth.false_mask
    assert mask.shape == f.image.shape and mask.any(axis=1).sum() > 20
    assert not frames["matte"][1].truth.false_mask.any()  # computed for shiny materials only
    near = _dilate(mask, 2) & off_line
    rad = f.laser_radiance.astype(float)
    assert near.sum() < 0.05 * off_line.sum()
    assert rad[near].sum() > 0.15 * rad[off_line].sum()  # a GGX lobe spreads the rest around it
    assert rad[near].mean() > 5 * rad[off_line & ~near].mean()
    assert f.truth.false_columns.shape[0] == f.image.shape[0]


def test_cache_key_covers_the_laser_passes(monkeypatch):
    s = scenes.make("cone", material="polished", cache=False, **SMALL)
    fields = s._cache_fields(0.0, 4, 0, "llvm_ad_mono")
    assert fields["laser_passes"] == [["path", 3, "object"], ["ptracer", 3, "other"]]
    assert "laser_passes" not in scenes.make("cone", material="matte", **SMALL)._cache_fields(0.0, 4, 0, "v")
    k = C.key(fields)
    from scenes import description

    monkeypatch.setattr(description, "laser_passes", lambda m: (description.LaserPass("ptracer", 3, "all"),))
    assert C.key(s._cache_fields(0.0, 4, 0, "llvm_ad_mono")) != k


def _row_fwhm(laser, truth, rows, half=12):
    from bench.studies.translucency import stripe_widths_px

    cols = np.full(laser.shape[0], np.nan)
    cols[rows] = truth[rows]
    fwhm, w1090, peak = stripe_widths_px(laser, cols, half)
    return np.nanmedian(fwhm[rows]), np.nanmedian(w1090[rows]), np.nanmedian(peak[rows])


def test_translucent_plane_has_a_wider_dimmer_stripe_and_the_same_truth(tmp_path):
    kw = dict(width=64, height=60, spp=8, ambient_spp=1, cache_dir=str(tmp_path))
    matte = scenes.make("plane", material="matte", **kw)
    theta = float(matte.default_angles()[24])
    fm = matte.render(theta)
    rows = np.nonzero(fm.truth.on_object)[0]
    assert rows.size > 50
    _, wm, pm = _row_fwhm(fm.laser_radiance, fm.truth.columns, rows, half=6)
    for material in ("skin", "marble", "wax"):
        f = scenes.make("plane", material=material, **kw).render(theta)
        # the medium does not move the surface: the same geometric truth
        assert np.array_equal(f.truth.columns, fm.truth.columns, equal_nan=True)
        assert np.array_equal(f.truth.on_object, fm.truth.on_object)
        _, w, p = _row_fwhm(f.laser_radiance, f.truth.columns, rows, half=6)
        assert w > 1.1 * wm, material  # the glow spreads the stripe (64 px: skin 1.7x, marble 1.15x)
        assert p < 0.8 * pm, material  # and lowers its peak


def test_translucent_renders_are_cached_with_their_optics_in_the_key(tmp_path, monkeypatch):
    from scenes import materials

    kw = dict(width=64, height=60, spp=4, ambient_spp=2, cache_dir=str(tmp_path))
    s = scenes.make("sphere", material="skin", **kw)
    fields = s._cache_fields(0.0, 4, 0, "v")
    assert fields["optics"]["medium"] == materials.medium("skin")
    assert fields["optics"]["laser_passes"] == [["volpath", materials.MEDIUM_MAX_DEPTH, "all"]]
    assert fields["optics"]["ambient_integrator"] == {"type": "volpath", "max_depth": materials.MEDIUM_MAX_DEPTH}
    assert fields["laser_passes"] == [["volpath", materials.MEDIUM_MAX_DEPTH, "all"]]
    assert "optics" not in scenes.make("sphere", material="matte", **kw)._cache_fields(0.0, 4, 0, "v")
    a = s.render(0.0)
    assert len(list(tmp_path.rglob("*.npz"))) == 1
    b = scenes.make("sphere", material="skin", **kw).render(0.0)  # from the cache
    assert np.array_equal(a.laser_radiance, b.laser_radiance) and len(list(tmp_path.rglob("*.npz"))) == 1
    # a changed coefficient is a different key: it re-renders
    t = materials.TRANSLUCENT["skin"]
    monkeypatch.setitem(materials.TRANSLUCENT, "skin", materials.Translucent(2 * t.sigma_s_reduced_per_mm,
                                                                              t.sigma_a_per_mm, t.source))
    c = scenes.make("sphere", material="skin", **kw).render(0.0)
    assert len(list(tmp_path.rglob("*.npz"))) == 2
    assert not np.array_equal(a.laser_radiance, c.laser_radiance)


def test_translucent_hand_is_one_medium_with_the_opaque_hands_truth(tmp_path):
    # the hand's overlapping parts are joined into one boundary (shapes.union) for the medium; its
    # outer surface is the parts' visible surface, so the truth is the opaque hand's to float rounding
    kw = dict(width=64, height=60, spp=4, ambient_spp=1, cache_dir=str(tmp_path), background="none",
              support="table")
    patchy = scenes.make("hand", material="patchy", **kw)
    skin = scenes.make("hand", material="skin", **kw)
    theta = float(patchy.default_angles()[8])
    tp, f = patchy.truth(theta), skin.render(theta)
    assert np.array_equal(f.truth.on_object, tp.on_object) and f.truth.on_object.sum() > 20
    ok = np.isfinite(tp.columns)
    assert np.array_equal(np.isfinite(f.truth.columns), ok)
    assert np.max(np.abs(f.truth.columns[ok] - tp.columns[ok])) < 1e-3  # px
    rows = np.nonzero(f.truth.on_object)[0]
    lit = f.laser_radiance[rows].sum(axis=1)
    assert np.all(np.isfinite(f.laser_radiance)) and np.median(lit) > 0  # the sheet reaches the medium


# -- textures and the colour camera -------------------------------------------------------------------------------

TINY = dict(width=64, height=60, spp=4, ambient_spp=2)


def _default_key_fields(s):
    return set(s._cache_fields(0.0, 4, 0, "llvm_ad_mono"))


def test_new_parameters_at_their_defaults_keep_the_mono_scene_and_its_key(tmp_path):
    s = scenes.make("cone", cache=False, **TINY)
    # the key's fields before the textures and the colour camera; `llvm_target` joined it with the
    # gate's renderer fix (docs/gate.md), not with them
    old_fields = ({"scene", "spp", "seed", "mirror_angle_deg", "rig", "variant", "mitsuba", "drjit", "llvm_target"}
                  | set(scenes.params.RENDER_KEYS) - {"spp", "seed"})
    assert _default_key_fields(s) == old_fields  # nothing new in an untextured key
    explicit = scenes.make("cone", cache=False, support_texture="none", background_texture="none",
                           object_texture="none", texture_scale_cm=2.0, texture_seed=0, support_finish="matte",
                           camera="mono", filter="bandpass", jpeg_quality=None, defocus_px=0.0, **TINY)
    k = C.key(s._cache_fields(0.0, 4, 0, "v"))
    assert C.key(explicit._cache_fields(0.0, 4, 0, "v")) == k
    # a colour camera without textures reuses the mono unit renders; textures, scale, seed re-render
    assert C.key(scenes.make("cone", camera="rgb", filter="none", **TINY)._cache_fields(0.0, 4, 0, "v")) == k
    tex = scenes.make("cone", background_texture="wood", **TINY)
    assert C.key(tex._cache_fields(0.0, 4, 0, "v")) != k
    for change in (dict(texture_scale_cm=3.0), dict(texture_seed=1), dict(camera="rgb"),
                   dict(ambient_illuminant="A"), dict(laser_wavelength_nm=640.0)):
        other = scenes.make("cone", background_texture="wood", **{**TINY, **change})
        assert C.key(other._cache_fields(0.0, 4, 0, "v")) != C.key(tex._cache_fields(0.0, 4, 0, "v")), change
    a, b = s.render(0.2), explicit.render(0.2)
    assert np.array_equal(a.image, b.image) and np.array_equal(a.radiance, b.radiance) and a.rgb is None


@pytest.fixture(scope="module")
def untextured(tmp_path_factory):
    d = str(tmp_path_factory.mktemp("untextured"))
    cone = scenes.make("cone", support="table", cache_dir=d, **TINY)
    _, part, _ = cone._visible(0.0)
    return cone.render(0.0), part, scenes.make("plane", cache_dir=d, **TINY).render(0.0)


@pytest.mark.parametrize("texture", scenes.textures.TEXTURES[1:])
def test_each_texture_renders_changes_the_image_and_not_the_truth(texture, untextured, tmp_path):
    plain, part, board0 = untextured
    f = scenes.make("cone", support="table", background_texture=texture, support_texture=texture,
                    cache_dir=str(tmp_path), **TINY).render(0.0)
    for name, k in (("wall", 0), ("table", 2)):
        seen = part == k
        assert seen.sum() > 20 and not np.array_equal(f.radiance[seen], plain.radiance[seen]), name
    assert np.array_equal(f.truth.columns, plain.truth.columns, equal_nan=True)
    assert np.array_equal(f.truth.points_cm, plain.truth.points_cm, equal_nan=True)
    assert np.array_equal(f.truth.part, plain.truth.part)
    g = scenes.make("plane", object_texture=texture, cache_dir=str(tmp_path), **TINY).render(0.0)
    assert not np.array_equal(g.radiance, board0.radiance)
    assert np.array_equal(g.truth.columns, board0.truth.columns, equal_nan=True)


def test_rgb_camera_frames(tmp_path):
    s = scenes.make("plane", object_texture="print", camera="rgb", filter="none", cache_dir=str(tmp_path), **TINY)
    f = s.render(0.0)
    assert f.rgb.shape == f.rgb_background.shape == (60, 64, 3) and f.rgb.dtype == np.uint8
    assert f.image.shape == (60, 64) and f.image.dtype == np.uint8
    assert f.radiance.shape == f.laser_radiance.shape == (60, 64, 3)
    assert np.array_equal(f.image, scenes.colour_camera.luma(f.rgb))
    # three ambient bands (a textured colour frame); the laser is red: the red channel carries it
    assert C.load(C.cache_root(str(tmp_path)), C.key(s._cache_fields(0.0, 4, 0, f.variant)))["ambient"].shape == (60, 64, 3)
    rows = np.nonzero(f.truth.valid)[0]
    cols = np.rint(f.truth.columns[rows]).astype(int)
    lit = f.rgb[rows, cols].astype(float) - f.rgb_background[rows, cols]
    assert np.median(lit[:, 0]) > 5 * max(1.0, np.median(np.abs(lit[:, 2])))
    again = s.render(0.0)
    assert np.array_equal(again.rgb, f.rgb)
    jpeg = scenes.make("plane", object_texture="print", camera="rgb", filter="none", jpeg_quality=75,
                       cache_dir=str(tmp_path), **TINY).render(0.0)
    assert not np.array_equal(jpeg.rgb, f.rgb) and np.abs(jpeg.rgb.astype(int) - f.rgb).mean() < 12


def test_a_white_paper_wall_white_balances_to_grey(tmp_path):
    for illuminant in ("A", "D65"):
        s = scenes.make("cone", background_texture="paper", camera="rgb", filter="none", laser_power_mw=0.0,
                        ambient_illuminant=illuminant, ambient_lux=400.0, exposure_ms=10.0,
                        cache_dir=str(tmp_path), width=64, height=60, spp=4, ambient_spp=16)
        f = s.render(0.0)
        _, on_object = s.visible_points(0.0)
        wall = f.rgb[~on_object].reshape(-1, 3).astype(float).mean(axis=0)
        assert wall.max() - wall.min() < 4.0, (illuminant, wall)


def test_mono_defocus_and_jpeg_act_on_the_image_only(tmp_path):
    base = dict(cache_dir=str(tmp_path), **TINY)
    a = scenes.make("cone", **base).render(0.0)
    b = scenes.make("cone", defocus_px=2.0, jpeg_quality=60, **base).render(0.0)
    assert np.array_equal(a.radiance, b.radiance) and np.array_equal(a.truth.columns, b.truth.columns,
                                                                     equal_nan=True)
    assert not np.array_equal(a.image, b.image)
    rows = np.nonzero(a.truth.on_object)[0]
    assert a.image[rows].max(axis=1).mean() > b.image[rows].max(axis=1).mean()  # the blur spreads the peak


def test_polished_table_splits_the_laser_pass_by_the_tables_pixels(tmp_path):
    s = scenes.make("sphere", support="table", background="none", support_finish="polished", cache=False, **TINY)
    fields = s._cache_fields(0.0, 4, 0, "v")
    assert fields["laser_passes"] == [["path", 3, "support"], ["ptracer", 3, "rest"]]
    assert fields["support_finish"] == "polished"
    mask = s.support_pixels(0.0)
    assert mask[-1].all() and not mask[0].any()  # the bottom row sees the table, the top row the sky
    f = s.render(0.0)
    matte = scenes.make("sphere", support="table", background="none", cache=False, **TINY).render(0.0)
    assert np.array_equal(f.truth.columns, matte.truth.columns, equal_nan=True)
    assert np.isfinite(f.laser_radiance).all() and not np.array_equal(f.radiance, matte.radiance)


@pytest.mark.slow
@pytest.mark.parametrize("name, background, support", [("sphere", "none", "table"), ("hand", "none", "table"),
                                                        ("plane", "wall", "none"), ("cone", "wall", "table")])
def test_lit_pixels_hold_every_pixel_with_direct_laser_light(name, background, support):
    # the whole-image direct light (bench.studies.perf.lit, here on a few frames at 128x120, among them
    # the limbs against the sky and the wall that a rule on the pixel centres alone missed)
    from bench.studies.perf.lit import check_frame

    s = scenes.make(name, background=background, support=support, width=128, height=120, cache=False)
    for theta in s.default_angles()[::3]:
        outside, share, lit_share = check_frame(s, float(theta), 16)
        assert outside == 0, (theta, share)
        assert 0.0 < lit_share < 0.25


def test_direct_light_passes_render_their_lit_pixels_only(monkeypatch):
    from scenes import backend

    s = scenes.make("cone", support="table", background="none", spp="auto", ambient_spp="auto", cache=False,
                    width=64, height=60)
    seen = []
    real = backend.LoadedScene.render

    def spy(self, updates, spp, seed, integrator=None, pixels=None):
        seen.append((integrator, None if pixels is None else pixels.copy()))
        return real(self, updates, spp, seed, integrator, pixels)

    monkeypatch.setattr(backend.LoadedScene, "render", spy)
    s.render(0.0)
    direct = [px for integ, px in seen if integ == ("path", 2)]
    assert len(direct) == 1 and np.array_equal(direct[0], s.lit_pixels(0.0))
    assert [px for integ, px in seen if integ == ("light_indirect", 3)] == [None]
    assert s._cache_fields(0.0, "auto", 0, "v")["camera_paths"] == scenes.scene.CAMERA_PATHS_VERSION
    assert "camera_paths" not in scenes.make("cone", cache=False, width=64, height=60)._cache_fields(0.0, 4, 0, "v")



def test_a_frames_laser_light_is_the_sum_of_its_passes_each_on_its_pixels():
    """``render_pass`` is how ``Scene.render`` renders a pass (the sampling procedure and ``perf scenes``
    use it too): a split frame's laser radiance is the sum over ``pass_pixels``, bit for bit, and each
    pass is zero off its pixels, the light tracer's whole-image render included."""
    from scenes import description
    from scenes.scene import render_pass

    s = scenes.make("cone", material="polished", support="table", background="none", spp="auto",
                    ambient_spp="auto", cache=False, width=64, height=60)
    theta = float(s.default_angles()[4])
    frame = s.render(theta)
    passes, counts, _ = s.sample_counts()
    masks = s.pass_pixels(theta, passes)
    assert [p.kind for p in passes] == ["path", "path", "light_indirect"] and all(m is not None for m in masks)
    laser = s._load()[0]
    pose = description.pose_updates(s.rig, theta)
    seeds = np.random.SeedSequence([s.params["seed"], *scenes.scene._angle_words(theta)]).spawn(4)
    seed = int(seeds[0].generate_state(1)[0])
    parts = [render_pass(laser, pose, p, m, n, seed) for p, m, n in zip(passes, masks, counts)]
    for part, mask in zip(parts, masks):
        assert part.dtype == np.float64 and not part[~mask].any()
    assert parts[2].any()  # the light tracer's bounce light lands on the other pixels
    total = np.zeros_like(parts[0])
    for part in parts:
        total += part
    unit = (total.astype(np.float32).astype(np.float64) * s.laser_power_inband_w()).astype(np.float32)
    assert np.array_equal(unit, frame.laser_radiance)

# -- translucency = "profile" --------------------------------------------------------------------------------------

def test_translucency_enters_the_cache_key_only_as_profile_of_a_translucent_material(monkeypatch):
    from scenes import materials, subsurface

    kw = dict(width=64, height=60, spp=4, ambient_spp=2, cache=False)
    skin = scenes.make("sphere", material="skin", **kw)
    fields = skin._cache_fields(0.0, 4, 0, "v")
    # the reference's key is what it was: no new field, the same optics
    assert fields == scenes.make("sphere", material="skin", translucency="volpath", **kw)._cache_fields(0.0, 4, 0, "v")
    assert "translucency" not in fields and set(fields["optics"]) == {"bsdf", "medium", "laser_passes",
                                                                       "ambient_integrator", "slab_thickness_cm",
                                                                       "boundary"}
    matte = scenes.make("sphere", material="matte", **kw)._cache_fields(0.0, 4, 0, "v")
    assert scenes.make("sphere", material="matte", translucency="profile", **kw)._cache_fields(0.0, 4, 0, "v") == matte
    prof = scenes.make("sphere", material="skin", translucency="profile", **kw)._cache_fields(0.0, 4, 0, "v")
    assert C.key(prof) != C.key(fields) and "laser_passes" not in prof
    assert prof["optics"]["translucency"] == "profile"
    assert prof["optics"]["profile"] == subsurface.spec_for("skin").key_fields()
    assert prof["optics"]["spread_version"] == subsurface.SPREAD_VERSION
    t = materials.TRANSLUCENT["skin"]
    monkeypatch.setitem(materials.TRANSLUCENT, "skin", materials.Translucent(t.sigma_s_reduced_per_mm, 2 * t.sigma_a_per_mm,
                                                                              t.source))
    other = scenes.make("sphere", material="skin", translucency="profile", **kw)._cache_fields(0.0, 4, 0, "v")
    assert C.key(other) != C.key(prof)  # a coefficient of the medium: another profile, another render


def test_profile_path_spreads_its_opaque_stand_in_into_a_wider_dimmer_stripe(tmp_path, monkeypatch):
    from scenes import subsurface

    kw = dict(width=64, height=60, spp=8, ambient_spp=2, cache=False, cache_dir=str(tmp_path), seed=1)
    s = scenes.make("plane", material="skin", translucency="profile", **kw)
    theta = float(s.default_angles()[24])
    f = s.render(theta)
    again = scenes.make("plane", material="skin", translucency="profile", **kw).render(theta)
    assert np.array_equal(f.radiance, again.radiance) and np.array_equal(f.image, again.image)
    monkeypatch.setattr(subsurface, "spread", lambda laser, *a, **k: laser)
    opaque = scenes.make("plane", material="skin", translucency="profile", **kw).render(theta)
    assert np.array_equal(f.truth.columns, opaque.truth.columns, equal_nan=True)
    amb, amb0 = f.radiance - f.laser_radiance, opaque.radiance - opaque.laser_radiance
    assert np.allclose(amb, amb0, rtol=0, atol=1e-6 * float(f.radiance.max()))  # the same ambient pass
    rows = np.nonzero(f.truth.on_object)[0]
    assert rows.size > 50
    _, w, p = _row_fwhm(f.laser_radiance, f.truth.columns, rows, half=6)
    _, w0, p0 = _row_fwhm(opaque.laser_radiance, f.truth.columns, rows, half=6)
    assert w > 1.2 * w0 and p < 0.8 * p0  # the glow: wider, lower peak
    # the stand-in's albedo is the medium's total diffuse reflectance, between Chandrasekhar's single
    # scattering (albedo / 8) and the albedo
    r = subsurface.table_for("skin").diffuse_reflectance
    a = scenes.materials.TRANSLUCENT["skin"].albedo_reduced
    assert a / 8 < r < a
