import math

import numpy as np
import pytest

from scenes import rig as R
from scenes.rig import Rig

THETAS = np.array([-7.5, -1.0, 0.0, 2.5, 11.0])


def test_default_zeta_images_20_and_60_cm_symmetrically():
    rig = Rig()
    for theta in THETAS:
        pts = R.cylindrical_to_cartesian([20.0, 60.0], rig.laser_phi_deg(theta), 0.0)
        px, _, _ = rig.sensor_coords_mm(pts, theta)
        assert px[0] == pytest.approx(-px[1], abs=1e-9)
    assert 13.5 < rig.zeta_deg < 14.5
    cols, _ = rig.project(R.cylindrical_to_cartesian([20.0, 60.0], rig.laser_phi_deg(0.0), 0.0), 0.0)
    assert 0.90 * rig.width < cols[0] < 0.97 * rig.width  # near 95 %
    assert 0.03 * rig.width < cols[1] < 0.10 * rig.width  # near 5 %


def test_symmetric_zeta_rejects_bad_ranges():
    with pytest.raises(ValueError, match="r_near_cm"):
        R.symmetric_zeta_deg(r_near_cm=60.0, r_far_cm=20.0)


@pytest.mark.parametrize("theta", THETAS)
def test_paper_equations_2_4_5_hold(theta):
    rig = Rig()
    r = np.linspace(20, 60, 9)
    z = np.linspace(-4, 4, 9)
    phi = 2 * theta - rig.zeta_deg  # eq. 4
    pts = R.cylindrical_to_cartesian(r, phi, z)
    # every such point lies on the laser plane
    p0, n = rig.laser_plane(theta)
    assert np.allclose((pts - p0) @ n, 0.0, atol=1e-12)
    cols, rows = rig.project(pts, theta)
    px, pz = rig.px_mm(cols), rig.pz_mm(rows)
    zeta = math.radians(rig.zeta_deg)
    f = rig.focal_mm
    depth = rig.d_m_cm + r * math.cos(zeta)
    assert np.allclose(px * depth, f * (rig.delta0_cm - r * math.sin(zeta)), atol=1e-10)  # eq. 2
    assert np.allclose(pz * depth, f * z, atol=1e-10)  # eq. 5 (d_m + d_r = D)


def test_camera_pose_and_axes():
    rig = Rig()
    for theta in THETAS:
        a, l = rig.optical_axis(theta), rig.lateral_axis(theta)
        t = math.radians(2 * theta)
        assert np.allclose(a, [math.sin(t), math.cos(t), 0])
        assert np.allclose(l, np.cross([0, 0, 1], a))
        assert np.allclose(rig.camera_center_cm(theta), -rig.d_m_cm * a + rig.delta0_cm * l)
        e = rig.laser_direction(theta)
        z = math.radians(rig.zeta_deg)
        assert np.allclose(e, math.cos(z) * a + math.sin(z) * l)
        assert np.allclose(rig.laser_origin_cm(theta), -rig.laser_distance_cm * e)
    # vectorised over theta
    assert rig.camera_center_cm(THETAS).shape == (len(THETAS), 3)


def test_pixel_rays_and_project_are_inverse():
    rig = Rig().with_size(128, 120)
    cols = np.array([0.0, 10.25, 63.5, 127.0])
    rows = np.array([0.0, 30.75, 59.5, 119.0])
    for theta in THETAS:
        o, d = rig.pixel_rays(cols, rows, theta)
        assert np.allclose(np.linalg.norm(d, axis=1), 1.0)
        pts = o + 37.0 * d
        c, r = rig.project(pts, theta)
        assert np.allclose(c, cols, atol=1e-9) and np.allclose(r, rows, atol=1e-9)


def test_principal_point_is_the_image_centre():
    rig = Rig()
    c, r = rig.project(rig.camera_center_cm(0.0) + 50 * rig.optical_axis(0.0), 0.0)
    assert c == pytest.approx(rig.width / 2 - 0.5) and r == pytest.approx(rig.height / 2 - 0.5)
    assert rig.px_mm(rig.width / 2 - 0.5) == 0.0 and rig.pz_mm(rig.height / 2 - 0.5) == 0.0


def test_with_size_keeps_the_field_of_view():
    big, small = Rig(), Rig().with_size(64, 60)
    assert small.pitch_x_mm == pytest.approx(big.pitch_x_mm * 8)
    assert small.pitch_y_mm == pytest.approx(big.pitch_y_mm * 8)
    pt = np.array([3.0, 40.0, 2.0])
    cb, rb = big.project(pt, 1.0)
    cs, rs = small.project(pt, 1.0)
    # continuous image positions (index + 0.5) scale by the pixel ratio
    assert (cs + 0.5) * 8 == pytest.approx(cb + 0.5) and (rs + 0.5) * 8 == pytest.approx(rb + 0.5)


def test_triangulating_with_the_paper_recovers_plane_points():
    rig = Rig()
    theta = 3.0
    o, d = rig.pixel_rays(np.array([40.3, 200.7, 470.1]), np.array([10.0, 240.0, 400.0]), theta)
    pts, _ = rig.intersect_laser_plane(o, d, theta)
    cols, rows = rig.project(pts, theta)
    px, pz = rig.px_mm(cols), rig.pz_mm(rows)
    z = math.radians(rig.zeta_deg)
    f = rig.focal_mm
    r = (f * rig.delta0_cm - px * rig.d_m_cm) / (f * math.sin(z) + px * math.cos(z))  # eq. 3
    zz = pz * (rig.delta0_cm - r * math.sin(z)) / px  # eq. 7
    back = R.cylindrical_to_cartesian(r, 2 * theta - rig.zeta_deg, zz)  # eq. 4
    assert np.allclose(back, pts, atol=1e-9)


def test_transform_helpers():
    assert np.allclose(R.apply_transform(R.rotation_z(90.0), [0, 1, 0]), [1, 0, 0])
    assert np.allclose(R.apply_transform(R.rotation_x(90.0), [0, 1, 0]), [0, 0, 1])
    m = R.look_at([1, 2, 3], [1, 5, 3])
    assert np.allclose(m[:3, 2], [0, 1, 0]) and np.allclose(m[:3, 1], [0, 0, 1])
    assert np.allclose(m[:3, 0], [-1, 0, 0])  # local +X = up x forward (the viewer's left)
    assert np.allclose(R.transform_normals(R.scaling([2, 1, 1]), [[1, 1, 0]]), [[1 / math.sqrt(5), 2 / math.sqrt(5), 0]])


@pytest.mark.slow
@pytest.mark.parametrize("theta", [0.0, 6.0])
def test_mitsuba_image_agrees_with_rig_project(theta):
    """A tiny glowing ball at a known point renders where Rig.project puts it (x sign, pixel centres)."""
    from scenes import description
    from scenes.backend import LoadedScene

    rig = Rig().with_size(128, 120)
    a, lat = rig.optical_axis(theta), rig.lateral_axis(theta)
    centre = rig.camera_center_cm(theta) + 50.0 * a - 2.1 * lat + 1.7 * np.array([0, 0, 1.0])  # right and up
    d = {"type": "scene", "integrator": {"type": "path", "max_depth": 2},
         "sensor": description.sensor(rig, theta, 256),
         "ball": {"type": "sphere", "center": (centre * R.CM_TO_M).tolist(), "radius": 0.002,
                  "emitter": {"type": "area", "radiance": 1.0}}}
    img = LoadedScene(d).render({}, 256, 3)
    rows, cols = np.mgrid[0:rig.height, 0:rig.width]
    w = img / img.sum()
    c_img, r_img = (w * cols).sum(), (w * rows).sum()
    c, r = rig.project(centre, theta)
    assert c > rig.width / 2 and r < rig.height / 2  # right of and above the centre
    assert c_img == pytest.approx(c, abs=0.1) and r_img == pytest.approx(r, abs=0.1)


def test_depth_of_column_inverts_the_projection_at_any_row_and_angle():
    """Eq. (3) from column alone returns R of points on the sheet projected by the rig (eq. 2)."""
    rig = Rig()
    r = np.array([19.0, 25.0, 32.8, 40.0, 55.0, 65.0])
    for theta in THETAS:
        for z in (-4.0, 0.0, 3.0):
            cols, _ = rig.project(R.cylindrical_to_cartesian(r, rig.laser_phi_deg(theta), z), theta)
            assert np.allclose(rig.depth_of_column_cm(cols), r, rtol=1e-12)


@pytest.mark.parametrize("size", [(512, 480), (128, 120)])
def test_imaged_range_is_where_the_sheet_leaves_the_image(size):
    rig = Rig().with_size(*size)
    for edges, (c_near, c_far) in ((False, (rig.width - 1, 0)), (True, (rig.width - 0.5, -0.5))):
        r_min, r_max = rig.imaged_range_cm(edges=edges)
        cols, _ = rig.project(R.cylindrical_to_cartesian([r_min, r_max], rig.laser_phi_deg(1.5), 2.0), 1.5)
        assert cols == pytest.approx([c_near, c_far], abs=1e-9)
    # the field of view is fixed: the strict limits do not depend on the pixel count
    assert rig.imaged_range_cm(edges=True) == pytest.approx(Rig().imaged_range_cm(edges=True), rel=1e-12)
    assert 18.0 < r_min < 19.5 and 65.0 < r_max < 67.0


def test_rig_docstring_examples_run():
    import doctest

    result = doctest.testmod(R)
    assert result.attempted > 0 and result.failed == 0
