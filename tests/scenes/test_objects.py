import numpy as np
import pytest

from scenes import objects as O
from scenes.rig import Rig


@pytest.mark.parametrize("name", O.OBJECTS)
def test_objects_sit_20_to_60_cm_from_the_axis_centred_on_the_laser(name):
    rig = Rig()
    obj = O.build(name, rig.zeta_deg)
    v = obj.mesh.vertices_cm
    r = np.hypot(v[:, 0], v[:, 1])
    assert r.min() > 20.0 and r.max() < 60.0
    phi_lo, phi_hi = obj.phi_range_deg
    assert 0.5 * (phi_lo + phi_hi) == pytest.approx(-rig.zeta_deg, abs=1.5)  # angle 0 crosses the middle
    # backdrop behind the object, inside 20-60 cm over the swept azimuths
    b = obj.backdrop.vertices_cm
    n = obj.backdrop.face_normals()[0]
    assert np.allclose(n, -rig.laser_direction(0.0))  # faces the axis
    assert np.all((v - b[0]) @ n > 0)  # whole object in front of the wall
    dist = O.BACKDROP_DISTANCE_CM / np.cos(np.radians(np.array(obj.phi_range_deg) + rig.zeta_deg))
    assert np.all(dist < 60.0)


@pytest.mark.parametrize("name", O.OBJECTS)
def test_default_angles_sweep_past_both_edges(name):
    rig = Rig()
    obj = O.build(name, rig.zeta_deg)
    angles = obj.default_angles(rig.zeta_deg, 48)
    assert len(angles) == 48 and np.all(np.diff(angles) > 0)
    phi = rig.laser_phi_deg(angles)
    assert phi[0] < obj.phi_range_deg[0] and phi[-1] > obj.phi_range_deg[1]
    assert np.mean(angles) == pytest.approx(0.0, abs=0.75)


def test_object_heights_fit_the_field():
    rig = Rig()
    for name in ("cone", "hand", "sphere"):
        z = O.build(name, rig.zeta_deg).mesh.vertices_cm[:, 2]
        assert z.max() <= 4.5 and z.min() >= -4.5


def test_unknown_object_lists_valid_names():
    with pytest.raises(KeyError, match="cone, hand, plane, sphere"):
        O.build("teapot", 14.0)


def test_out_of_range_distance_is_beyond_what_the_rig_images():
    rig = Rig()
    d = O.out_of_range_distance_cm()
    assert d == pytest.approx(rig.imaged_range_cm(edges=True)[1] + O.OUT_OF_RANGE_MARGIN_CM)
    assert O.out_of_range_distance_cm(margin_cm=0.0) == pytest.approx(rig.imaged_range_cm(edges=True)[1])
    # a wall at that distance: its stripe lies left of the image at every default angle of every object
    e0, lat = rig.laser_direction(0.0), np.cross(rig.laser_direction(0.0), [0.0, 0.0, 1.0])
    for name in O.OBJECTS:
        for theta in O.build(name, rig.zeta_deg).default_angles(rig.zeta_deg, 48):
            e = rig.laser_direction(theta)
            p = (d / (e @ e0)) * e + np.array([0.0, 0.0, 1.0]) * np.linspace(-5, 5, 5)[:, None]
            assert np.allclose(p @ e0, d)  # on the wall
            cols, _ = rig.project(p, theta)
            assert np.all(cols < -0.5 - 30.0)  # more than 30 px outside the image
    with pytest.raises(ValueError, match=r"`margin_cm` must be a finite number >= 0, got -1.0"):
        O.out_of_range_distance_cm(margin_cm=-1.0)


@pytest.mark.parametrize("distance", [45.0, 55.0, 80.0])
def test_wall_distance_and_size_follow_the_parameter(distance):
    rig = Rig()
    obj = O.build("sphere", rig.zeta_deg, "wall", distance)
    b = obj.backdrop.vertices_cm
    e0 = rig.laser_direction(0.0)
    assert np.allclose(b @ e0, distance)
    assert np.ptp(b[:, 2]) == pytest.approx(O.BACKDROP_SIZE_CM[1] * distance / O.BACKDROP_DISTANCE_CM)
    assert O.build("sphere", rig.zeta_deg, "none", distance).backdrop is None


def test_default_geometry_is_unchanged():
    rig = Rig()
    obj = O.build("cone", rig.zeta_deg)
    assert obj.support is None
    old = O.shapes.rectangle(*O.BACKDROP_SIZE_CM).transformed(O._placement(55.0, rig.zeta_deg))
    assert np.array_equal(obj.backdrop.vertices_cm, old.vertices_cm)
    explicit = O.build("cone", rig.zeta_deg, "wall", 55.0, "none")
    assert np.array_equal(obj.backdrop.vertices_cm, explicit.backdrop.vertices_cm) and explicit.support is None


def test_wall_must_stand_behind_the_object():
    with pytest.raises(ValueError, match=r"`background_distance_cm` must put the wall behind the cone .*got 40.0"):
        O.build("cone", Rig().zeta_deg, "wall", 40.0)
    assert O.build("cone", Rig().zeta_deg, "none", 40.0).backdrop is None  # no wall, nothing to check
    with pytest.raises(ValueError, match=r"`background` must be one of 'wall', 'none', got 'sky'"):
        O.build("cone", Rig().zeta_deg, "sky")
    with pytest.raises(ValueError, match=r"`support` must be one of 'none', 'table', got 'shelf'"):
        O.build("cone", Rig().zeta_deg, support="shelf")


@pytest.mark.parametrize("background", O.BACKGROUNDS)
@pytest.mark.parametrize("name", O.OBJECTS)
def test_table_is_under_the_object_and_fills_the_view_below_it(name, background):
    rig = Rig().with_size(128, 120)
    obj = O.build(name, rig.zeta_deg, background, 55.0, "table")
    t = obj.support.vertices_cm
    top = obj.mesh.vertices_cm[:, 2].min()
    assert np.allclose(t[:, 2], top)  # its top at the object's lowest point
    assert np.allclose(obj.support.face_normals(), [0.0, 0.0, 1.0])  # facing up
    e0 = rig.laser_direction(0.0)
    lat = np.cross(e0, [0.0, 0.0, 1.0])
    far = 55.0 if background == "wall" else O.out_of_range_distance_cm()
    assert (t @ e0).min() == pytest.approx(0.0, abs=1e-9) and (t @ e0).max() == pytest.approx(far)
    half = np.abs(t @ lat).max()
    rows, cols = np.meshgrid(np.arange(rig.height, dtype=float), np.arange(rig.width, dtype=float), indexing="ij")
    for theta in np.linspace(-O.TABLE_MAX_MIRROR_ANGLE_DEG, O.TABLE_MAX_MIRROR_ANGLE_DEG, 9):
        o, d = rig.pixel_rays(cols, rows, theta)
        with np.errstate(divide="ignore"):
            s = (top - o[..., 2]) / d[..., 2]
        p = o + s[..., None] * d
        down = s > 0  # rays that reach the table's plane
        nearer = down & (p @ e0 <= far)  # ... before the wall / the far edge
        assert np.all(np.abs(p[nearer] @ lat) < half) and np.all(p[nearer] @ e0 > 0)
        # every pixel of the bottom row looks down onto the table, in front of the far edge
        assert np.all(nearer[-1])
    # rows below the object's image see the table only, over the default scan
    for theta in obj.default_angles(rig.zeta_deg, 8):
        _, obj_rows = rig.project(obj.mesh.vertices_cm, theta)
        o, d = rig.pixel_rays(cols, rows, theta)
        s = (top - o[..., 2]) / d[..., 2]
        p = o + s[..., None] * d
        below = rows > obj_rows.max() + 0.5
        assert np.all((s[below] > 0) & (p[below] @ e0 <= far) & (np.abs(p[below] @ lat) < half))


def test_objects_docstring_examples_run():
    import doctest

    result = doctest.testmod(O)
    assert result.attempted > 0 and result.failed == 0


def test_texture_maps_measure_each_surface_in_cm():
    o = O.build("plane", Rig().zeta_deg, "wall", 55.0, "table")
    m = o.uv_to_cm["object"]
    uv = o.mesh.uv
    cm = (np.c_[uv, np.ones(len(uv))] @ m.T)[:, :2]
    # the board's corners land on its own 14 x 12 cm (its planar projection undone)
    assert np.allclose(np.sort(np.abs(cm), axis=0), [[7, 6]] * 4, atol=1e-9)
    assert np.allclose(o.uv_to_cm["backdrop"], np.diag([90.0, 40.0, 1.0]))
    assert np.allclose(o.uv_to_cm["support"][1, 1], 55.0)
    far = O.build("cone", Rig().zeta_deg, "wall", 110.0)
    assert np.allclose(far.uv_to_cm["backdrop"], np.diag([180.0, 80.0, 1.0])) and "support" not in far.uv_to_cm
    cone = O.build("cone", Rig().zeta_deg)
    assert np.allclose(np.diag(cone.uv_to_cm["object"]), [8.0, 8.6, 1.0], atol=0.05)
