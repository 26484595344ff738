import math

import numpy as np
import pytest

from scenes.rig import Rig, cylindrical_to_cartesian
from scenes.truth import false_stripe_mask, ground_truth

RIG = Rig().with_size(128, 120)
ZETA = RIG.zeta_deg


class Analytic:
    """Float64 ray caster for a wall (part 0) and optional spheres (part 1); spheres in ``occluders`` get part 2."""

    def __init__(self, wall_point, wall_normal, spheres=(), occluders=()):
        self.w0 = np.asarray(wall_point, float)
        self.wn = np.asarray(wall_normal, float) / np.linalg.norm(wall_normal)
        self.spheres = [(np.asarray(c, float), r, 1) for c, r in spheres] + \
                       [(np.asarray(c, float), r, 2) for c, r in occluders]

    def __call__(self, o, d):
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((self.w0 - o) @ self.wn) / (d @ self.wn)
        t = np.where(t > 1e-9, t, np.inf)
        part = np.where(np.isfinite(t), 0, -1)
        for c, r, k in self.spheres:
            oc = o - c
            b = np.einsum("ij,ij->i", oc, d)
            disc = b * b - (np.einsum("ij,ij->i", oc, oc) - r * r)
            with np.errstate(invalid="ignore"):
                ts = -b - np.sqrt(disc)
            ts = np.where((disc > 0) & (ts > 1e-9), ts, np.inf)
            closer = ts < t
            t = np.where(closer, ts, t)
            part = np.where(closer, k, part)
        return t, part


def _wall(theta_lo=0.0, distance=55.0):
    e = RIG.laser_direction(theta_lo)
    return Analytic(distance * e, -e)


def _expected_on_wall(caster, theta):
    """Independent solution: laser plane ∩ wall plane ∩ the plane of the row's rays."""
    cols, pts = np.full(RIG.height, np.nan), np.full((RIG.height, 3), np.nan)
    c = RIG.camera_center_cm(theta)
    a, l = RIG.optical_axis(theta), RIG.lateral_axis(theta)
    _, n = RIG.laser_plane(theta)
    for r in range(RIG.height):
        pz = RIG.pz_mm(r)
        row_normal = np.cross(l, RIG.focal_mm * a + pz * np.array([0, 0, 1.0]))
        m = np.stack([n, caster.wn, row_normal])
        rhs = np.array([0.0, caster.w0 @ caster.wn, row_normal @ c])
        p = np.linalg.solve(m, rhs)
        col, row = RIG.project(p, theta)
        assert row == pytest.approx(r, abs=1e-9)
        cols[r], pts[r] = col, p
    return cols, pts


@pytest.mark.parametrize("theta", [-4.0, 0.0, 3.0])
def test_wall_truth_matches_three_plane_intersection(theta):
    cast = _wall()
    truth = ground_truth(RIG, theta, cast, fan_deg=90.0)
    cols, pts = _expected_on_wall(cast, theta)
    assert np.all(truth.valid)
    assert np.allclose(truth.columns, cols, atol=1e-5)
    assert np.allclose(truth.points_cm, pts, atol=1e-5)
    assert not truth.on_object.any()


def test_truth_points_are_exact_ray_plane_intersections_that_triangulate():
    theta = 1.0
    truth = ground_truth(RIG, theta, _wall(), fan_deg=90.0)
    rows = np.arange(RIG.height)
    o, d = RIG.pixel_rays(truth.columns, rows, theta)
    p, _ = RIG.intersect_laser_plane(o, d, theta)
    assert np.array_equal(p, truth.points_cm)
    px, pz = RIG.px_mm(truth.columns), RIG.pz_mm(rows)
    z, f = math.radians(ZETA), RIG.focal_mm
    r = (f * RIG.delta0_cm - px * RIG.d_m_cm) / (f * math.sin(z) + px * math.cos(z))
    height = pz * (RIG.delta0_cm - r * math.sin(z)) / px
    back = cylindrical_to_cartesian(r, 2 * theta - ZETA, height)
    assert np.allclose(back, truth.points_cm, atol=1e-6)


def test_sphere_points_lie_on_the_sphere_and_silhouettes_are_rejected():
    theta = 0.9  # the sheet cuts the sphere off-centre: its stripe ends at the silhouette
    centre = cylindrical_to_cartesian(38.0, -ZETA, 0.0)
    cast = Analytic(55.0 * RIG.laser_direction(0.0), -RIG.laser_direction(0.0), spheres=[(centre, 4.3)])
    truth = ground_truth(RIG, theta, cast, fan_deg=90.0)
    on = truth.on_object
    assert on.sum() > 40
    assert np.allclose(np.linalg.norm(truth.points_cm[on] - centre, axis=1), 4.3, atol=1e-6)
    back = truth.valid & ~on
    assert np.allclose((truth.points_cm[back] - cast.w0) @ cast.wn, 0.0, atol=1e-6)
    # the sign change of the signed distance at the sphere's silhouette is never reported:
    # every valid point is on one of the surfaces (checked above) and on the laser plane
    _, n = RIG.laser_plane(theta)
    assert np.allclose(truth.points_cm[truth.valid] @ n, 0.0, atol=1e-9)
    # rows above/below the sphere see the wall stripe, except where the sphere shadows it
    assert back.sum() > 0


def test_shadowed_points_are_rejected():
    theta = 0.0
    e = RIG.laser_direction(theta)
    src = RIG.laser_origin_cm(theta)
    blocker = src + 3.0 * e  # a 1 mm ball in the sheet, 3 cm in front of the laser
    cast = Analytic(55.0 * e, -e, occluders=[(blocker, 0.1)])
    truth = ground_truth(RIG, theta, cast, fan_deg=90.0)
    plain = ground_truth(RIG, theta, _wall(), fan_deg=90.0)
    v = plain.points_cm - src
    elev = np.degrees(np.arctan2(v[:, 2], np.hypot(v[:, 0], v[:, 1])))
    half = math.degrees(math.asin(0.1 / 3.0))
    assert np.all(np.isnan(truth.columns[np.abs(elev) < half - 0.1]))
    assert np.all(np.isfinite(truth.columns[np.abs(elev) > half + 0.1]))
    assert 0 < np.isnan(truth.columns).sum() < RIG.height


def test_points_outside_the_fan_are_rejected():
    theta = 0.0
    truth = ground_truth(RIG, theta, _wall(), fan_deg=4.0)
    plain = ground_truth(RIG, theta, _wall(), fan_deg=90.0)
    v = plain.points_cm - RIG.laser_origin_cm(theta)
    elev = np.degrees(np.arctan2(v[:, 2], np.hypot(v[:, 0], v[:, 1])))
    assert np.array_equal(np.isfinite(truth.columns), np.abs(elev) <= 2.0)


def test_nothing_hit_gives_nan():
    def miss(o, d):
        return np.full(len(o), np.inf), np.full(len(o), -1)

    truth = ground_truth(RIG, 0.0, miss, fan_deg=90.0)
    assert truth.columns.shape == (RIG.height,) and np.all(np.isnan(truth.columns))
    assert truth.points_cm.shape == (RIG.height, 3) and not truth.on_object.any()


class SphereOnFloor:
    """Float64 caster: a sphere (part 1) standing on an endless floor ``z = z0`` (part 2), nothing else."""

    def __init__(self, centre, radius):
        self.c, self.r = np.asarray(centre, float), float(radius)
        self.z0 = self.c[2] - self.r

    def __call__(self, o, d):
        with np.errstate(divide="ignore", invalid="ignore"):
            tf = (self.z0 - o[:, 2]) / d[:, 2]
        t = np.where(tf > 1e-9, tf, np.inf)
        part = np.where(np.isfinite(t), 2, -1)
        oc = o - self.c
        b = np.einsum("ij,ij->i", oc, d)
        disc = b * b - (np.einsum("ij,ij->i", oc, oc) - self.r ** 2)
        with np.errstate(invalid="ignore"):
            ts = -b - np.sqrt(disc)
        ts = np.where((disc > 0) & (ts > 1e-9), ts, np.inf)
        closer = ts < t
        return np.where(closer, ts, t), np.where(closer, 1, part)


def test_part_labels_the_object_and_the_floor_and_nothing_else():
    theta = 0.0
    centre = cylindrical_to_cartesian(38.0, -ZETA, 0.0)
    cast = SphereOnFloor(centre, 4.3)
    truth = ground_truth(RIG, theta, cast, fan_deg=90.0)
    assert truth.part.dtype == np.int8 and truth.part.shape == (RIG.height,)
    assert set(np.unique(truth.part)) == {-1, 1, 2}  # no background anywhere
    assert np.array_equal(truth.on_object, truth.part == 1)
    assert np.array_equal(truth.valid, truth.part >= 0)
    on, floor = np.nonzero(truth.part == 1)[0], np.nonzero(truth.part == 2)[0]
    assert np.allclose(np.linalg.norm(truth.points_cm[on] - centre, axis=1), 4.3, atol=1e-6)
    assert np.allclose(truth.points_cm[floor, 2], cast.z0, atol=1e-6)
    # the floor's stripe continues the sphere's below it down to the last row; above the sphere
    # the sheet hits nothing (rows without truth)
    assert floor.min() > on.max() and floor.max() == RIG.height - 1
    assert np.all(np.isnan(truth.columns[:on.min()]))


class WallAndDiskMirror:
    """Float64 caster with normals: the wall (part 0) and a flat disk mirror (part 1)."""

    def __init__(self, wall, centre, normal, radius_cm):
        self.wall = wall
        self.c = np.asarray(centre, float)
        self.n = np.asarray(normal, float) / np.linalg.norm(normal)
        self.r = radius_cm

    def __call__(self, o, d):
        t, part = self.wall(o, d)
        nrm = np.where(np.isfinite(t)[:, None], self.wall.wn, np.nan)
        with np.errstate(divide="ignore", invalid="ignore"):
            tm = ((self.c - o) @ self.n) / (d @ self.n)
        hit = o + np.where(np.isfinite(tm), tm, 0.0)[:, None] * d
        on_disk = (tm > 1e-9) & (np.linalg.norm(hit - self.c, axis=1) <= self.r)
        closer = on_disk & (tm < t)
        t = np.where(closer, tm, t)
        part = np.where(closer, 1, part)
        nrm = np.where(closer[:, None], self.n, nrm)
        return t, part, nrm


def _mirror_scene(theta, lateral=1.0, up=0.1):
    """A disk mirror 30 cm out along the laser, turned to throw a tilted sheet onto the wall."""
    e = RIG.laser_direction(theta)
    _, n_sheet = RIG.laser_plane(theta)
    normal = -0.1 * e + lateral * n_sheet + up * np.array([0.0, 0.0, 1.0])
    return WallAndDiskMirror(_wall(theta), 30.0 * e, normal, 3.0)


def test_false_stripe_of_a_flat_mirror_is_the_mirrored_sheet_on_the_wall():
    theta = 0.0
    scene = _mirror_scene(theta)
    mask = false_stripe_mask(RIG, theta, scene, fan_deg=90.0)
    assert mask.sum() > 40 and mask.any(axis=1).sum() > 40
    # independent solution: the mirrored sheet is the plane through the mirror image of the laser
    # pinhole with the mirrored normal; it meets the wall in a 3-D line, projected to an image line
    m = scene.n
    householder = np.eye(3) - 2.0 * np.outer(m, m)
    src = RIG.laser_origin_cm(theta)
    src_img = scene.c + householder @ (src - scene.c)
    _, n_sheet = RIG.laser_plane(theta)
    n_ref = householder @ n_sheet
    w0, wn = scene.wall.w0, scene.wall.wn
    direction = np.cross(n_ref, wn)
    a = np.stack([n_ref, wn, direction])
    p0 = np.linalg.solve(a, np.array([n_ref @ src_img, wn @ w0, direction @ w0]))
    u0, v0 = RIG.project(p0 - 30.0 * direction, theta)
    u1, v1 = RIG.project(p0 + 30.0 * direction, theta)
    rows, cols = np.nonzero(mask)
    dist = np.abs((u1 - u0) * (v0 - rows) - (u0 - cols) * (v1 - v0)) / np.hypot(u1 - u0, v1 - v0)
    assert dist.max() <= 0.5 * math.sqrt(2.0) + 1e-6  # pixel centres nearest to points on the line
    # and every marked pixel sees the wall inside the mirror's reflected footprint
    o, d = RIG.pixel_rays(cols.astype(float), rows.astype(float), theta)
    t, part = scene.wall(o, d)
    assert np.all(part == 0)
    q = o + t[:, None] * d
    to_src = src_img - q  # the virtual ray from the pinhole's image to q crosses the disk
    s = ((scene.c - q) @ m) / (to_src @ m)
    assert np.all(np.linalg.norm(q + s[:, None] * to_src - scene.c, axis=1) <= 3.0 + 0.2)


def test_no_false_stripe_without_a_mirror_hit_or_when_reflected_out_of_view():
    theta = 0.0
    empty = false_stripe_mask(RIG, theta, _mirror_scene(theta, lateral=0.0, up=0.0), fan_deg=90.0)
    assert empty.shape == (RIG.height, RIG.width) and not empty.any()  # sent straight back to the laser
    wall_only = _wall(theta)

    def cast(o, d):
        t, part = wall_only(o, d)
        return t, part, np.where(np.isfinite(t)[:, None], wall_only.wn, np.nan)

    assert not false_stripe_mask(RIG, theta, cast, fan_deg=90.0).any()
