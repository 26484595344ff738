import math

import numpy as np
import pytest

from scenes import shapes as S


def _welded_edges_used_twice(m: S.Mesh) -> bool:
    _, inv = np.unique(m.vertices_cm.round(9), axis=0, return_inverse=True)
    f = inv.reshape(-1)[m.faces]
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


def _volume(m: S.Mesh) -> float:
    v = m.vertices_cm[m.faces]
    return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6.0)


CLOSED = {
    "sphere": (lambda: S.uv_sphere(4.3), 4 / 3 * math.pi * 4.3 ** 3),
    "cone": (lambda: S.cone(4.0, 8.6), math.pi * 16 * 8.6 / 3),
    "capsule": (lambda: S.capsule(0.8, 6.0), math.pi * 0.64 * 6.0 + 4 / 3 * math.pi * 0.8 ** 3),
    "slab": (lambda: S.superellipsoid(4.3, 1.2, 3.6, exponent=1.0), 4 / 3 * math.pi * 4.3 * 1.2 * 3.6),
}


@pytest.mark.parametrize("name", sorted(CLOSED))
def test_closed_meshes_are_watertight_outward_and_have_the_right_volume(name):
    build, volume = CLOSED[name]
    m = build()
    assert _welded_edges_used_twice(m)
    # outward: geometric face normals agree with the analytic vertex normals
    vn = m.normals[m.faces].mean(axis=1)
    assert np.all(np.einsum("ij,ij->i", m.face_normals(), vn) > 0.5)
    assert _volume(m) == pytest.approx(volume, rel=5e-3)
    assert np.allclose(np.linalg.norm(m.normals[np.unique(m.faces)], axis=1), 1.0)


def test_cone_apex_is_up_and_sphere_is_centred():
    c = S.cone(4.0, 8.6)
    top = c.vertices_cm[np.argmax(c.vertices_cm[:, 2])]
    assert np.allclose(top, [0, 0, 4.3])
    s = S.uv_sphere(2.0)
    assert np.allclose(np.linalg.norm(s.vertices_cm, axis=1), 2.0)


def test_capsule_runs_along_x():
    m = S.capsule(0.5, 3.0)
    lo, hi = m.vertices_cm.min(0), m.vertices_cm.max(0)
    assert np.allclose(lo, [-0.5, -0.5, -0.5]) and np.allclose(hi, [3.5, 0.5, 0.5])


def test_hand_fits_the_vertical_field_and_is_hand_sized():
    h = S.hand()
    lo, hi = h.vertices_cm.min(0), h.vertices_cm.max(0)
    assert hi[2] <= 4.5 and lo[2] >= -4.5  # camera's vertical field at 45-50 cm
    assert 14.0 < hi[0] - lo[0] < 18.0  # palm + fingers
    assert np.allclose(0.5 * (lo[0] + hi[0]), 0.0) and np.allclose(0.5 * (lo[2] + hi[2]), 0.0)
    # every part is a closed surface, so the union is one (vertices are not shared between parts)
    assert _welded_edges_used_twice(h)
    # five fingers: a vertical line through the finger region crosses four separate fingers
    # a vertical line of front-to-back rays through the fingers hits four separate fingers
    zs = np.arange(-4.45, 4.5, 0.05)
    occupied = np.array([_hits_along_y(h, 4.0, z) for z in zs])
    runs = np.sum(np.diff(occupied.astype(int)) == 1) + int(occupied[0])
    assert runs == 4


def _hits_along_y(m: S.Mesh, x: float, z: float) -> bool:
    """Does the line {(x, y, z)} cross the mesh?  (2-D point-in-triangle test in the x-z plane.)"""
    v = m.vertices_cm[m.faces][:, :, [0, 2]]
    p = np.array([x, z])
    def cross2(a, b):
        return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]

    d = [cross2(v[:, (k + 1) % 3] - v[:, k], p - v[:, k]) for k in range(3)]
    return bool(np.any(((d[0] >= 0) & (d[1] >= 0) & (d[2] >= 0)) | ((d[0] <= 0) & (d[1] <= 0) & (d[2] <= 0))))


def test_rectangle_faces_minus_y():
    r = S.rectangle(2.0, 3.0)
    assert np.allclose(r.face_normals(), [0, -1, 0])


def test_transformed_moves_vertices_and_normals():
    m = S.rectangle(2.0, 2.0)
    rot = np.eye(4)
    rot[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    t = m.transformed(rot)
    assert np.allclose(t.face_normals(), [1, 0, 0]) and np.allclose(t.normals, [1, 0, 0])


def test_planar_uv_spans_the_unit_square_with_v_down():
    m = S.planar_uv(S.uv_sphere(1.0, 16, 8))
    assert m.uv.min() == pytest.approx(0.0) and m.uv.max() == pytest.approx(1.0)
    top = np.argmax(m.vertices_cm[:, 2])
    assert m.uv[top, 1] == pytest.approx(0.0)


def test_merge_offsets_faces():
    a, b = S.rectangle(1, 1), S.rectangle(1, 1)
    m = S.merge([a, b])
    assert len(m.vertices_cm) == 8 and m.faces.max() == 7


def _signed_volume(m):
    p = m.vertices_cm[m.faces]
    return np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0


def test_sphere_and_cone_are_closed_and_outward():
    sphere = S.uv_sphere(4.3)
    cone = S.cone(4.0, 8.6)
    assert S.is_closed(sphere) and S.is_closed(cone)
    assert len(S.boundary_edges(sphere)) == 0
    # outward winding: the enclosed volume is positive and near the analytic one
    assert _signed_volume(sphere) == pytest.approx(4 / 3 * np.pi * 4.3**3, rel=2e-3)
    assert _signed_volume(cone) == pytest.approx(np.pi * 4.0**2 * 8.6 / 3, rel=2e-3)


def test_rectangle_is_open_and_solidify_closes_it_behind_its_face():
    r = S.rectangle(14.0, 12.0)
    assert not S.is_closed(r) and len(S.boundary_edges(r)) == 4
    slab = S.solidify(r, 2.0)
    assert S.is_closed(slab)
    assert _signed_volume(slab) == pytest.approx(14.0 * 12.0 * 2.0)
    # the front keeps its triangles; the slab lies behind it (local +Y, away from the rig)
    assert np.array_equal(slab.faces[:2], r.faces) and slab.vertices_cm[:, 1].min() == 0.0
    assert slab.vertices_cm[:, 1].max() == pytest.approx(2.0)
    assert S.solidify(S.uv_sphere(1.0, 16, 8), 1.0).faces.shape == S.uv_sphere(1.0, 16, 8).faces.shape
    with pytest.raises(ValueError, match="`thickness_cm` must be > 0, got 0"):
        S.solidify(r, 0)


def test_hand_parts_are_closed_but_overlap():
    # every part is closed, so the edge test passes, but a palm and a finger overlap: the merged
    # parts are not one boundary (a medium needs the union, below)
    hand = S.hand()
    assert S.is_closed(hand) and S.components(hand) == 6
    palm = S.superellipsoid(4.3, 1.2, 3.6, exponent=0.45)
    assert _signed_volume(hand) > _signed_volume(palm) > 0
    # a finger's root lies inside the palm: some hand vertices are strictly inside another part
    lo, hi = hand.vertices_cm.min(0), hand.vertices_cm.max(0)
    assert np.all(hi - lo > 0)
    finger = S._segment(S.capsule(0.78, 7.6), [3.2, 0.0, 0.9], [1.0, 0.0, 0.0])
    inside = ((finger.vertices_cm[:, 0] / 4.3) ** 2 + (finger.vertices_cm[:, 1] / 1.2) ** 2 < 1.0) & \
        (np.abs(finger.vertices_cm[:, 2]) < 3.6)
    assert inside.any()


def test_union_of_two_overlapping_spheres_is_one_closed_lens_free_volume():
    a = S.uv_sphere(1.0, 32, 16)
    b = a.transformed(np.array([[1, 0, 0, 1.0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float))
    u = S.union(S.merge([a, b]))
    assert S.is_closed(u) and S.components(u) == 1
    # union volume = 2 V - lens (two unit spheres 1 apart: lens = 5 pi / 12), to the facets' accuracy
    assert _signed_volume(u) == pytest.approx(2 * _signed_volume(a) - 5 * np.pi / 12, rel=1e-2)
    assert np.allclose(np.linalg.norm(u.normals, axis=1), 1.0)
    # no vertex of the result lies strictly inside either sphere (the buried walls are gone)
    r_a = np.linalg.norm(u.vertices_cm, axis=1)
    r_b = np.linalg.norm(u.vertices_cm - [1.0, 0, 0], axis=1)
    assert np.all(np.maximum(r_a, r_b) > 0.99)
    # disjoint pieces stay separate pieces
    far = a.transformed(np.array([[1, 0, 0, 5.0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], float))
    assert S.components(S.union(S.merge([a, far]))) == 2
    with pytest.raises(ValueError, match="closed"):
        S.union(S.rectangle(1.0, 1.0))


def test_hand_union_is_one_closed_boundary_with_the_same_outer_surface():
    hand = S.planar_uv(S.hand())
    u = S.union(hand)
    assert S.is_closed(u) and S.components(u) == 1
    assert 0 < _signed_volume(u) < _signed_volume(hand)  # the overlaps are counted once
    # every vertex of the union lies on the surface of the parts: on a part's triangle plane,
    # within float32 rounding (manifold3d works in float32 here), and none is buried in the palm
    lo, hi = u.vertices_cm.min(0), u.vertices_cm.max(0)
    assert np.allclose(lo, hand.vertices_cm.min(0), atol=1e-4) and np.allclose(hi, hand.vertices_cm.max(0), atol=1e-4)
    # texture coordinates follow the planar projection (linear in position, so interpolation is exact)
    assert np.allclose(S.planar_uv(u).uv, u.uv, atol=1e-5)


def test_medium_boundary_picks_the_closing_step():
    sphere = S.uv_sphere(1.0, 16, 8)
    assert S.medium_boundary(sphere, 2.0) is sphere
    assert S.components(S.medium_boundary(S.hand(), 2.0)) == 1
    slab = S.medium_boundary(S.rectangle(2.0, 1.0), 0.5)
    assert S.is_closed(slab) and _signed_volume(slab) == pytest.approx(1.0)


def test_docstring_examples():
    import doctest

    assert doctest.testmod(S, raise_on_error=False).failed == 0
