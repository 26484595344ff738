"""Eqs. (3), (4), (7) against the rig's forward model and the renderer's truth."""

import numpy as np
import pytest

import scenes
from bench.evaluate.triangulation import cylindrical_to_cartesian, depth_cm, triangulate
from scenes import Rig


@pytest.mark.parametrize("theta", [-6.0, -1.3, 0.0, 2.5, 7.0])
@pytest.mark.parametrize("size", [(512, 480), (128, 120)])
def test_round_trip_through_the_rigs_forward_model(theta, size):
    rig = Rig().with_size(*size)
    rng = np.random.default_rng(0)
    r = rng.uniform(20, 60, 200)
    z = rng.uniform(-4, 4, 200)
    phi = 2 * theta - rig.zeta_deg
    pts = cylindrical_to_cartesian(r, phi, z)
    cols, rows = rig.project(pts, theta)
    r2, phi2, z2 = triangulate(cols, rows, theta, rig)
    assert np.allclose(r2, r, atol=1e-9) and np.allclose(z2, z, atol=1e-9)
    assert np.allclose(phi2, phi, atol=1e-12)
    assert np.abs(cylindrical_to_cartesian(r2, phi2, z2) - pts).max() < 1e-6


def test_depth_is_independent_of_row_and_mirror_angle():
    rig = Rig()
    cols = np.array([10.0, 256.0, 500.0])
    r1, _, _ = triangulate(cols, 3.0, 1.0, rig)
    r2, _, _ = triangulate(cols, 400.0, -5.0, rig)
    assert np.array_equal(r1, r2) and np.array_equal(r1, depth_cm(cols, rig))


def test_far_is_left_and_near_is_right():
    rig = Rig()
    r = depth_cm(np.array([30.0, 480.0]), rig)
    assert 55 < r[0] < 62 and 19 < r[1] < 22


def test_eq7_singular_column_uses_the_equivalent_form():
    rig = Rig()
    r0 = rig.delta0_cm / np.sin(np.radians(rig.zeta_deg))  # P_x = 0 here
    col = rig.col_of_px(0.0)
    pts = cylindrical_to_cartesian(r0, -rig.zeta_deg, 3.0)
    _, row = rig.project(pts, 0.0)
    r, phi, z = triangulate(col, row, 0.0, rig)
    assert np.isfinite(z) and abs(r - r0) < 1e-9 and abs(z - 3.0) < 1e-9
    # a hair away from P_x = 0, eq. (7) itself agrees with the equivalent form
    r1, _, z1 = triangulate(col + 1e-3, row, 0.0, rig)
    f = rig.focal_mm / 10
    assert abs(z1 - rig.pz_mm(row) / 10 * (rig.d_m_cm + r1 * np.cos(np.radians(rig.zeta_deg))) / f) < 1e-9


def test_nan_columns_give_nan():
    r, phi, z = triangulate([np.nan, 100.0], [5, 5], 0.0, Rig())
    assert np.isnan(r[0]) and np.isnan(phi[0]) and np.isnan(z[0]) and np.isfinite(r[1])


@pytest.mark.parametrize("theta", [-2.0, 0.0, 1.5])
def test_rendered_ground_truth_columns_triangulate_to_ground_truth_points(theta):
    scene = scenes.make("cone", material="matte", width=64, height=60, spp=1, ambient_spp=1, cache=False)
    frame = scene.render(theta)
    ok = frame.truth.valid
    assert ok.sum() > 10
    rows = np.flatnonzero(ok)
    r, phi, z = triangulate(frame.truth.columns[ok], rows, theta, scene.rig)
    pts = cylindrical_to_cartesian(r, phi, z)
    assert np.abs(pts - frame.truth.points_cm[ok]).max() < 1e-6
