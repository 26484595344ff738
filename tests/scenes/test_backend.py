"""Mitsuba-backed checks at 128x120 (slow: Mitsuba JIT)."""

import math

import numpy as np
import pytest

from scenes import description as D, laser, objects, shapes
from scenes.backend import LoadedScene
from scenes.rig import Rig

pytestmark = pytest.mark.slow

RIG = Rig().with_size(128, 120)


@pytest.fixture(scope="module")
def wall_only():
    """The default backdrop with the object hidden far behind it."""
    obj = objects.build("sphere", RIG.zeta_deg)
    hidden = shapes.rectangle(1.0, 1.0).transformed(np.diag([1.0, 1.0, 1.0, 1.0]) + np.pad(
        [[0, 0, 0, 0], [0, 0, 0, 300.0], [0, 0, 0, 0]], ((0, 1), (0, 0))))
    return objects.SceneObject("wall", hidden, obj.backdrop, obj.phi_range_deg)


def _wall_coordinates(theta):
    """Float64 wall points of pixel edges along the middle row and the row's index."""
    e0 = RIG.laser_direction(0.0)
    w0, wn = 55.0 * e0, -e0
    row = RIG.height // 2
    edges = np.arange(RIG.width + 1) - 0.5
    o, d = RIG.pixel_rays(edges, np.full(edges.shape, float(row)), theta)
    t = ((w0 - o) @ wn) / (d @ wn)
    return o + t[:, None] * d, row


def test_laser_line_carries_its_power_onto_the_wall(wall_only):
    """Lambertian wall at 65 cm from the laser: ∫ L ds across the line = ρ/π · P / (2 tan(fan/2) d)."""
    prof = laser.profile(3.0, 90.0)
    scene = LoadedScene(D.laser_scene(RIG, wall_only, "matte", prof, 0.0, 16))
    img = scene.render(D.pose_updates(RIG, 0.0), 16, 1).astype(float)
    pts, row = _wall_coordinates(0.0)
    _, n = RIG.laser_plane(0.0)
    s_m = (pts @ n) * 0.01  # across-the-line coordinate on the wall (m) of the pixel edges
    integral = np.sum(img[row] * np.abs(np.diff(s_m)))
    d_m = (55.0 + RIG.laser_distance_cm) * 0.01
    expected = 0.5 / math.pi * 1.0 / (2 * prof.tan_half_y * d_m)
    assert integral == pytest.approx(expected, rel=0.02)
    # and the line is where the laser plane meets the wall
    centre = np.sum(img[row] * np.arange(RIG.width)) / img[row].sum()
    c_expected = np.interp(0.0, s_m, np.arange(RIG.width + 1) - 0.5)
    assert centre == pytest.approx(c_expected, abs=0.1)


def test_unit_sky_on_an_open_wall_gives_its_albedo(wall_only):
    scene = LoadedScene(D.ambient_scene(RIG, wall_only, "matte", 0.0, 16))
    img = scene.render(D.pose_updates(RIG, 0.0), 16, 2)
    assert img.mean() == pytest.approx(0.5, rel=0.005)
    assert img.std() < 0.05 * 0.5  # Monte Carlo noise of the sky's visibility sampling


def test_rays_hit_the_wall_where_geometry_says(wall_only):
    scene = LoadedScene(D.ambient_scene(RIG, wall_only, "matte", 0.0, 1))
    theta = 1.5
    o, d = RIG.pixel_rays(np.array([3.0, 64.0, 120.0]), np.array([5.0, 60.0, 110.0]), theta)
    t, part = scene.cast(o, d, ("backdrop", "object"))
    e0 = RIG.laser_direction(0.0)
    t_ref = ((55.0 * e0 - o) @ -e0) / (d @ -e0)
    assert np.allclose(t, t_ref, rtol=2e-6)
    assert np.all(part == 0)
    t2, part2 = scene.cast(o, -d, ("backdrop", "object"))  # away from everything
    assert np.all(np.isinf(t2)) and np.all(part2 == -1)


def test_renders_are_reproducible_and_pose_independent(wall_only):
    scene = LoadedScene(D.laser_scene(RIG, wall_only, "matte", laser.profile(3.0, 90.0), 0.0, 4))
    a = scene.render(D.pose_updates(RIG, 1.0), 4, 11)
    scene.render(D.pose_updates(RIG, -2.0), 4, 12)
    b = scene.render(D.pose_updates(RIG, 1.0), 4, 11)
    assert np.array_equal(a, b)


def test_ctrl_c_inside_a_render_is_a_keyboard_interrupt(wall_only, monkeypatch):
    # Dr.Jit wraps a Ctrl-C that arrives inside some renders (the light-traced pass) in a RuntimeError;
    # the backend turns it back into KeyboardInterrupt, and leaves other errors alone
    scene = LoadedScene(D.ambient_scene(RIG, wall_only, "matte", 0.0, 1))

    def wrapped(*args, **kwargs):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as k:
            raise RuntimeError("drjit.custom(...): error while performing a custom operation") from k

    monkeypatch.setattr(scene._mi, "render", wrapped)
    with pytest.raises(KeyboardInterrupt):
        scene.render(D.pose_updates(RIG, 0.0), 1, 0)

    def broken(*args, **kwargs):
        raise RuntimeError("something else")

    monkeypatch.setattr(scene._mi, "render", broken)
    with pytest.raises(RuntimeError, match="something else"):
        scene.render(D.pose_updates(RIG, 0.0), 1, 0)


def test_light_traced_direct_light_carries_the_lines_power_onto_the_wall(wall_only):
    # light_indirect at depth 2 splats every light path at its first surface: the direct light, with
    # the same closed-form line integral and line centre as the path tracer's (first test above)
    prof = laser.profile(3.0, 90.0)
    scene = LoadedScene(D.laser_scene(RIG, wall_only, "matte", prof, 0.0, 16))
    # 128 light paths per pixel: about 16,000 cross the middle row, 0.8 % noise on its integral
    img = scene.render(D.pose_updates(RIG, 0.0), 128, 1, integrator=("light_indirect", 2)).astype(float)
    pts, row = _wall_coordinates(0.0)
    _, n = RIG.laser_plane(0.0)
    s_m = (pts @ n) * 0.01
    integral = np.sum(img[row] * np.abs(np.diff(s_m)))
    d_m = (55.0 + RIG.laser_distance_cm) * 0.01
    assert integral == pytest.approx(0.5 / math.pi / (2 * prof.tan_half_y * d_m), rel=0.03)
    centre = np.sum(img[row] * np.arange(RIG.width)) / img[row].sum()
    assert centre == pytest.approx(np.interp(0.0, s_m, np.arange(RIG.width + 1) - 0.5), abs=0.1)
    # nothing but the wall: no light path has a second surface to reach the camera from
    assert not scene.render(D.pose_updates(RIG, 0.0), 4, 1, integrator=("light_indirect", 3)).any()


@pytest.fixture(scope="module")
def cone_on_table():
    import scenes

    s = scenes.make("cone", material="matte", support="table", background="none", width=128, height=120,
                    cache=False)
    return s._load(16)[0], D.pose_updates(s.rig, 0.0)


def test_light_traced_bounce_light_is_ptracers_depth_difference(cone_on_table):
    # expectation: ptracer at 3 minus ptracer at 2 (same seed: exactly the depth-3 splats);
    # measured spread of one 16-spp total here: 3 % (light_indirect) and 4 % (ptracer difference),
    # so 4 seeds each put the ratio of means within 10 % at over 4 standard deviations
    scene, pose = cone_on_table
    ours = [scene.render(pose, 16, seed, integrator=("light_indirect", 3)).astype(float) for seed in range(4)]
    theirs = [scene.render(pose, 16, 10 + seed, integrator=("ptracer", 3)).astype(float)
              - scene.render(pose, 16, 10 + seed, integrator=("ptracer", 2)) for seed in range(4)]
    assert min(img.min() for img in ours) >= 0.0
    assert np.sum(theirs) > 0
    assert np.sum(ours) / np.sum(theirs) == pytest.approx(1.0, abs=0.1)


def test_light_traced_passes_do_not_depend_on_the_thread_count(cone_on_table):
    import drjit as dr

    scene, pose = cone_on_table
    if not scene.variant.startswith("llvm"):
        pytest.skip(f"thread count applies to LLVM variants, this is {scene.variant}")
    a = scene.render(pose, 4, 3, integrator=("light_indirect", 3))
    threads = dr.thread_count()
    dr.set_thread_count(1)
    try:
        b = scene.render(pose, 4, 3, integrator=("light_indirect", 3))
    finally:
        dr.set_thread_count(threads)
    assert a.any() and np.array_equal(a, b)
    assert not np.array_equal(a, scene.render(pose, 4, 4, integrator=("light_indirect", 3)))


@pytest.mark.parametrize("kwargs, match", [({"depth": 1}, "`depth` must be >= 2"),
                                           ({"spp": 0}, "`spp` must be >= 1, got 0")])
def test_light_indirect_names_a_bad_argument(cone_on_table, kwargs, match):
    from scenes.backend import light_indirect

    scene, _ = cone_on_table
    args = {"spp": 1, "seed": 0, "depth": 3, **kwargs}
    with pytest.raises(ValueError, match=match):
        light_indirect(scene._mi, scene._scene, **args)


def test_camera_paths_on_some_pixels_estimate_what_the_whole_image_render_does(cone_on_table):
    # the integrator's own per-ray estimate on chosen pixels: the same expectation per pixel as
    # mi.render masked to them; measured spread of the stripe's 16-spp total here about 1 %
    scene, pose = cone_on_table
    whole = np.mean([scene.render(pose, 16, seed, integrator=("path", 2)) for seed in range(4)], axis=0)
    pixels = whole > 0
    pixels[1::2] = False  # the stripe on every other row
    part = np.mean([scene.render(pose, 16, 10 + seed, integrator=("path", 2), pixels=pixels)
                    for seed in range(4)], axis=0)
    assert not part[~pixels].any()
    assert part[pixels].sum() == pytest.approx(whole[pixels].sum(), rel=0.03)
    # the stripe's centre per row: the footprint's positions are the pixels', not shifted
    rows = np.nonzero(np.where(pixels, whole, 0.0).sum(axis=1) > 0.2 * whole.sum(axis=1).max())[0]
    cols = np.arange(whole.shape[1])

    def centre(img):
        return (img[rows] * cols).sum(axis=1) / img[rows].sum(axis=1)

    assert len(rows) > 5
    assert np.median(np.abs(centre(part) - centre(np.where(pixels, whole, 0.0)))) < 0.05
    # reproducible, and an empty mask renders nothing
    assert np.array_equal(scene.render(pose, 4, 1, integrator=("path", 2), pixels=pixels),
                          scene.render(pose, 4, 1, integrator=("path", 2), pixels=pixels))
    assert not scene.render(pose, 4, 1, integrator=("path", 2), pixels=np.zeros_like(pixels)).any()


def test_camera_paths_name_a_mask_of_the_wrong_shape(cone_on_table):
    from scenes.backend import camera_paths

    scene, _ = cone_on_table
    with pytest.raises(ValueError, match=r"`pixels` must have the film's shape \(120, 128\), got \(3, 4\)"):
        camera_paths(scene._mi, scene._scene, scene._scene.integrator(), np.ones((3, 4), bool), 1, 0)


@pytest.fixture(scope="module")
def polished_hand():
    import scenes
    from scenes.scene import _laser_profile

    s = scenes.make("hand", material="polished", support="table", background="none", width=128, height=120,
                    cache=False)
    theta = float(s.default_angles()[7])
    loaded, pose = s._load(16)[0], D.pose_updates(s.rig, theta)
    loaded.set_pose(pose)
    fov = _laser_profile(s.params["line_fwhm_mrad"], s.params["laser_fan_deg"]).fov_x_deg
    return loaded, pose, s.split_pixels(theta), fov


def test_the_mis_bounce_light_estimates_what_the_path_tracers_bounce_does(polished_hand):
    # camera paths and light paths of one bounce, each weighted by the balance heuristic, sum to the
    # one-bounce light: path at depth 3 minus path at depth 2 on the object's pixels (same seed);
    # measured spread of one total here: 4.4 % (ours, 16 + 4) and 3.6 % (path, 16), so 4 seeds each
    # put the ratio of means within 10 % at about 3.5 standard deviations (measured 0.985)
    from scenes.backend import bounce_mis, light_indirect

    loaded, pose, objpx, fov = polished_hand
    mi, scene = loaded._mi, loaded._scene
    ours, theirs = [], []
    for seed in range(4):
        camera = bounce_mis(mi, scene, objpx, 16, seed, 4, fov)
        light = light_indirect(mi, scene, 4, 100 + seed, 3, mis=(objpx, 16, fov))
        assert not camera[~objpx].any() and camera.min() >= 0.0
        ours.append(camera[objpx].sum() + light[objpx].sum())
        theirs.append(loaded.render(pose, 16, 200 + seed, integrator=("path", 3), pixels=objpx)[objpx].sum()
                      - loaded.render(pose, 16, 200 + seed, integrator=("path", 2), pixels=objpx)[objpx].sum())
    assert np.sum(theirs) > 0
    assert np.sum(ours) / np.sum(theirs) == pytest.approx(1.0, abs=0.1)


def test_the_mis_light_pass_weights_its_splats_on_its_pixels_only(polished_hand):
    from scenes.backend import light_indirect

    loaded, _, objpx, fov = polished_hand
    mi, scene = loaded._mi, loaded._scene
    plain = light_indirect(mi, scene, 4, 7, 3)
    weighted = light_indirect(mi, scene, 4, 7, 3, mis=(objpx, 16, fov))
    assert np.array_equal(plain[~objpx], weighted[~objpx])  # the same paths, weight 1 off the pixels
    assert (weighted <= plain).all() and weighted[objpx].sum() < plain[objpx].sum()  # weights in [0, 1]
    # the camera paths' weight goes to 1 as the light paths' count falls, and the light's to 0
    assert light_indirect(mi, scene, 4, 7, 3, mis=(objpx, 65536, fov))[objpx].sum() < 0.1 * plain[objpx].sum()


@pytest.mark.parametrize("call, match", [
    (lambda b, mi, sc, px, fov: b.bounce_mis(mi, sc, px[:3], 4, 0, 2, fov),
     r"`pixels` must have the film's shape \(120, 128\)"),
    (lambda b, mi, sc, px, fov: b.bounce_mis(mi, sc, px, 4, 0, 0, fov), "`light_spp` must be an integer >= 1, got 0"),
    (lambda b, mi, sc, px, fov: b.light_indirect(mi, sc, 4, 0, 2, mis=(px, 4, fov)), "`mis` needs `depth` = 3"),
    (lambda b, mi, sc, px, fov: b.light_indirect(mi, sc, 4, 0, 3, mis=(px[:3], 4, fov)),
     r"`mis` pixels must have shape \(120, 128\)")])
def test_the_mis_passes_name_a_bad_argument(polished_hand, call, match):
    from scenes import backend

    loaded, _, objpx, fov = polished_hand
    with pytest.raises(ValueError, match=match):
        call(backend, loaded._mi, loaded._scene, objpx, fov)


def test_a_loaded_scene_renders_both_halves_of_the_mis_bounce_light(polished_hand):
    from scenes.backend import bounce_mis, light_indirect

    loaded, pose, objpx, fov = polished_hand
    both = loaded.bounce_mis(pose, objpx, 4, 2, 5)
    camera = bounce_mis(loaded._mi, loaded._scene, objpx, 4, 5, 2, fov)
    light = light_indirect(loaded._mi, loaded._scene, 2, 6, 3, mis=(objpx, 4, fov))
    assert np.array_equal(both, camera + np.where(objpx, light, 0.0).astype(np.float32))
    assert both[objpx].any() and not both[~objpx].any()


def test_only_a_laser_scene_renders_the_mis_bounce_light():
    import scenes

    s = scenes.make("cone", material="polished", width=64, height=60, cache=False)
    ambient = s._load(4)[1]
    with pytest.raises(ValueError, match="bounce_mis needs a laser scene on a JIT variant"):
        ambient.bounce_mis(D.pose_updates(s.rig, 0.0), np.ones((60, 64), bool), 4, 2, 0)
