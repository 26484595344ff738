"""Per-row ground truth: where the laser plane meets the visible, lit surface.

Algorithm (float64 except inside the ray caster):

1. Cast one ray through every pixel centre; ``s = n · hit`` is the signed
   distance of the visible surface to the laser plane (``n`` from
   :meth:`scenes.Rig.laser_plane`).
2. Every sign change of ``s`` between horizontally adjacent pixels is a
   candidate crossing.
3. Refine each candidate on the *continuous* column with a bracketed
   Illinois (modified regula falsi) iteration, bisecting after any step that
   failed to halve the bracket, one batched ray cast per step, until the bracket is below ``1e-6`` px
   or the hit is within ``1e-6`` cm of the plane (the surface itself is float32,
   so the column is exact to about 1e-4 px; the iteration is not the limit).
4. Reject silhouettes: at a depth discontinuity the iteration converges to the
   jump, where the surface is still far from the plane (``|s| > plane_tol_cm``).
5. The ground-truth point is the float64 intersection of the pixel ray through
   ``(column, row centre)`` with the laser plane, so triangulating the column
   with the paper's equations returns it to rounding error.
6. Reject points outside the laser's fan and points in its shadow (a ray from the
   laser pinhole hits something more than ``shadow_tol_cm`` before the point).
7. If a row keeps several crossings (a surface folding through the plane), keep
   the one nearest the laser: it is lit first along the sheet and is the bright
   one in practice.  (None of the built-in objects does this over their default
   scans except at finger/palm junctions of ``hand``.)

The ray caster is injected, so the algorithm is testable against analytic
geometry without Mitsuba.
"""

from __future__ import annotations

from typing import Callable, Optional, Tuple

import numpy as np

from .frame import Truth, false_columns
from .rig import Rig

__all__ = ["ground_truth", "CastFn", "CastNormalsFn", "false_stripe_mask", "false_columns"]

CastFn = Callable[[np.ndarray, np.ndarray], Tuple[np.ndarray, np.ndarray]]
"""``cast(origins_cm (N, 3), unit_dirs (N, 3)) -> (t_cm (N,) inf on miss, part (N,) int, -1 on miss)``."""


def _signed(rig: Rig, theta_deg: float, cast: CastFn, cols: np.ndarray, rows: np.ndarray):
    o, d = rig.pixel_rays(cols, rows, theta_deg)
    t, part = cast(o.reshape(-1, 3), d.reshape(-1, 3))
    t = t.reshape(cols.shape)
    part = part.reshape(cols.shape)
    _, normal = rig.laser_plane(theta_deg)
    with np.errstate(invalid="ignore"):
        hit = o + np.where(np.isfinite(t), t, np.nan)[..., None] * d
    return hit @ normal, part


def ground_truth(rig: Rig, theta_deg: float, cast: CastFn, *, fan_deg: float, object_part: int = 1,
                 tol_px: float = 1e-6, g_tol_cm: float = 1e-6, max_iter: int = 40, plane_tol_cm: float = 1e-3,
                 shadow_tol_cm: float = 0.02, centre_points_cm: Optional[np.ndarray] = None) -> Truth:
    """Ground truth of one frame.

    Parameters
    ----------
    rig : Rig
    theta_deg : float
        Mirror angle.
    cast : CastFn
        Batched ray caster (cm).
    fan_deg : float
        Full vertical fan angle of the laser.
    object_part : int
        Part index ``cast`` returns for the object (sets ``on_object``; every index is kept in
        ``Truth.part``).
    tol_px, g_tol_cm, max_iter, plane_tol_cm, shadow_tol_cm : float
        Iteration stops when the bracket is below ``tol_px`` or the hit is within ``g_tol_cm`` of the
        plane (float32 ray casting resolves about 1e-6 cm); iteration cap; silhouette and shadow
        tolerances.
    centre_points_cm : ndarray (H, W, 3), optional
        The first hits of the rays through the pixel centres (``rig.pixel_rays``, NaN on a miss) when
        the caller has cast them already: step 1 then uses them instead of casting.

    Returns
    -------
    Truth
    """
    h, w = rig.height, rig.width
    rows_grid, cols_grid = np.meshgrid(np.arange(h, dtype=float), np.arange(w, dtype=float), indexing="ij")
    if centre_points_cm is None:
        s, _ = _signed(rig, theta_deg, cast, cols_grid, rows_grid)
    else:
        s = np.asarray(centre_points_cm, float).reshape(h, w, 3) @ rig.laser_plane(theta_deg)[1]
    a, b = s[:, :-1], s[:, 1:]
    with np.errstate(invalid="ignore"):
        cand = np.isfinite(a) & np.isfinite(b) & ((a * b < 0) | ((a == 0) & (b != 0)))
    r_idx, c_idx = np.nonzero(cand)
    columns = np.full(h, np.nan)
    points = np.full((h, 3), np.nan)
    on_object = np.zeros(h, bool)
    parts = np.full(h, -1, np.int8)
    if len(r_idx) == 0:
        return Truth(columns, points, on_object, parts)

    rows = r_idx.astype(float)
    xl, xr = c_idx.astype(float), c_idx + 1.0
    gl, gr = a[r_idx, c_idx].copy(), b[r_idx, c_idx].copy()
    x = xl.copy()
    side = np.zeros(len(rows), int)  # Illinois: which end was retained last
    alive = np.ones(len(rows), bool)
    done = gl == 0
    x[done] = xl[done]
    bisect = np.zeros(len(rows), bool)  # after a step that failed to halve the bracket
    for _ in range(max_iter):
        width_before = xr - xl
        act = alive & ~done & (xr - xl > tol_px)
        if not act.any():
            break
        i = np.nonzero(act)[0]
        xi = xr[i] - gr[i] * (xr[i] - xl[i]) / (gr[i] - gl[i])
        bad = ~np.isfinite(xi) | (xi <= xl[i]) | (xi >= xr[i]) | bisect[i]
        xi[bad] = 0.5 * (xl[i][bad] + xr[i][bad])
        gi, _ = _signed(rig, theta_deg, cast, xi, rows[i])
        x[i] = xi
        miss = ~np.isfinite(gi)
        alive[i[miss]] = False
        ok = ~miss
        i, xi, gi = i[ok], xi[ok], gi[ok]
        zero = np.abs(gi) <= g_tol_cm
        done[i[zero]] = True
        i, xi, gi = i[~zero], xi[~zero], gi[~zero]
        same_as_left = np.sign(gi) == np.sign(gl[i])
        li, ri = i[same_as_left], i[~same_as_left]
        # root in [x, xr]: move left end; Illinois halves the stale right value on repeats
        xl[li], gl[li] = xi[same_as_left], gi[same_as_left]
        gr[li] = np.where(side[li] == -1, 0.5 * gr[li], gr[li])
        side[li] = -1
        xr[ri], gr[ri] = xi[~same_as_left], gi[~same_as_left]
        gl[ri] = np.where(side[ri] == 1, 0.5 * gl[ri], gl[ri])
        side[ri] = 1
        bisect[:] = (xr - xl) > 0.5 * width_before
    undone = alive & ~done
    x[undone] = xr[undone] - gr[undone] * (xr[undone] - xl[undone]) / (gr[undone] - gl[undone])
    bad = undone & ~((x >= xl) & (x <= xr))
    x[bad] = 0.5 * (xl[bad] + xr[bad])

    # silhouettes: the surface must actually reach the plane at x
    g, part = _signed(rig, theta_deg, cast, x, rows)
    keep = alive & np.isfinite(g) & (np.abs(g) <= plane_tol_cm)
    o, d = rig.pixel_rays(x, rows, theta_deg)
    p, _ = rig.intersect_laser_plane(o, d, theta_deg)

    # fan and shadow
    src = rig.laser_origin_cm(theta_deg)
    v = p - src
    dist = np.linalg.norm(v, axis=1)
    horiz = np.hypot(v[:, 0], v[:, 1])
    forward = v @ rig.laser_direction(theta_deg) > 0
    keep &= forward & (np.degrees(np.abs(np.arctan2(v[:, 2], horiz))) <= 0.5 * fan_deg)
    if keep.any():
        k = np.nonzero(keep)[0]
        t_l, _ = cast(np.broadcast_to(src, (len(k), 3)).copy(), v[k] / dist[k, None])
        keep[k[t_l < dist[k] - shadow_tol_cm]] = False

    # one crossing per row: nearest to the laser
    k = np.nonzero(keep)[0]
    order = np.lexsort((dist[k], r_idx[k]))
    k = k[order]
    first = np.ones(len(k), bool)
    first[1:] = r_idx[k][1:] != r_idx[k][:-1]
    k = k[first]
    rr = r_idx[k]
    columns[rr] = x[k]
    points[rr] = p[k]
    on_object[rr] = part[k] == object_part
    parts[rr] = part[k]
    return Truth(columns, points, on_object, parts)


CastNormalsFn = Callable[[np.ndarray, np.ndarray], Tuple[np.ndarray, np.ndarray, np.ndarray]]
"""``cast(origins_cm (N, 3), unit_dirs (N, 3)) -> (t_cm (N,), part (N,), unit_normals (N, 3))``, as
:data:`CastFn` plus the surface normal at each hit (NaN on a miss)."""


def _sheet_dirs(rig: Rig, theta_deg: float, elevations_rad: np.ndarray) -> np.ndarray:
    e = rig.laser_direction(theta_deg)
    el = np.asarray(elevations_rad, float)[:, None]
    return np.cos(el) * e + np.sin(el) * np.array([0.0, 0.0, 1.0])


def false_stripe_mask(rig: Rig, theta_deg: float, cast: CastNormalsFn, *, fan_deg: float, object_part: int = 1,
                      rays_per_row: int = 8, offset_cm: float = 1e-3, visible_tol_cm: float = 0.05) -> np.ndarray:
    """Pixels where the laser sheet, mirrored once by the object, lands on a surface the camera sees.

    Algorithm (float64 except inside the ray caster):

    1. Cast rays from the laser pinhole inside the sheet (elevations spanning the fan), first
       coarsely, then ``rays_per_row`` rays per image row's worth of elevation over the elevation
       range that hits the object.
    2. Keep the rays whose first hit is the object; reflect each about the surface normal there
       (``r = d - 2 (d·n) n``, the mirror direction: the centre of a rough material's lobe).
    3. Cast the reflected rays (from ``offset_cm`` off the surface); a hit on any surface (the
       backdrop, the object itself) is a false-stripe point.
    4. Project the point into the camera; mark its pixel if it lies inside the image, in front of
       the camera and is the first surface along the pixel's ray (within ``visible_tol_cm``).

    Parameters
    ----------
    rig : Rig
    theta_deg : float
        Mirror angle.
    cast : CastNormalsFn
        Batched ray caster (cm) that also returns normals.
    fan_deg : float
        Full vertical fan angle of the laser.
    object_part : int
        Part index ``cast`` returns for the object.
    rays_per_row : int
        Sheet rays per image row's worth of elevation angle (the reflected stripe is dotted when a
        convex surface spreads it more than this).
    offset_cm, visible_tol_cm : float
        Self-intersection offset of the reflected rays; visibility tolerance.

    Returns
    -------
    mask : ndarray (H, W), bool
        True on pixels that see a point of the once-reflected sheet.
    """
    h, w = rig.height, rig.width
    mask = np.zeros((h, w), bool)
    src = rig.laser_origin_cm(theta_deg)
    half = 0.5 * np.radians(fan_deg)
    coarse = np.linspace(-half, half, 4 * h + 1)
    t, part, _ = cast(np.broadcast_to(src, (len(coarse), 3)).copy(), _sheet_dirs(rig, theta_deg, coarse))
    hit = np.nonzero(part == object_part)[0]
    if len(hit) == 0:
        return mask
    step = coarse[1] - coarse[0]
    lo, hi = coarse[max(hit[0] - 1, 0)], coarse[min(hit[-1] + 1, len(coarse) - 1)]
    row_angle = np.arctan(rig.pitch_y_mm / rig.focal_mm)  # one row's elevation near the axis
    n_fine = int(np.ceil((hi - lo) / row_angle * rays_per_row)) + 1
    fine = np.linspace(lo, hi, max(n_fine, int(round((hi - lo) / step)) + 1))
    d = _sheet_dirs(rig, theta_deg, fine)
    o = np.broadcast_to(src, d.shape).copy()
    t, part, nrm = cast(o, d)
    keep = (part == object_part) & np.isfinite(t) & np.all(np.isfinite(nrm), axis=1)
    if not keep.any():
        return mask
    d, p, nrm = d[keep], o[keep] + t[keep, None] * d[keep], nrm[keep]
    cos = np.sum(d * nrm, axis=1)
    nrm = np.where(cos[:, None] > 0, -nrm, nrm)  # face the incoming ray
    r = d - 2.0 * np.sum(d * nrm, axis=1)[:, None] * nrm
    r /= np.linalg.norm(r, axis=1, keepdims=True)
    t2, _, _ = cast(p + offset_cm * nrm, r)
    ok = np.isfinite(t2)
    if not ok.any():
        return mask
    q = p[ok] + offset_cm * nrm[ok] + t2[ok, None] * r[ok]
    cols, rows = rig.project(q, theta_deg)
    _, _, depth = rig.sensor_coords_mm(q, theta_deg)
    c, v = np.round(cols).astype(np.int64), np.round(rows).astype(np.int64)
    inside = (depth > 0) & (c >= 0) & (c < w) & (v >= 0) & (v < h)
    if not inside.any():
        return mask
    q, c, v = q[inside], c[inside], v[inside]
    cam = rig.camera_center_cm(theta_deg)
    to_q = q - cam
    dist = np.linalg.norm(to_q, axis=1)
    t3, _, _ = cast(np.broadcast_to(cam, q.shape).copy(), to_q / dist[:, None])
    seen = t3 >= dist - visible_tol_cm
    mask[v[seen], c[seen]] = True
    return mask

