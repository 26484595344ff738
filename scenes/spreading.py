"""Line-spread kernels of a surface point's local geometry, and the spreading of the opaque stripe along image rows.

The second half of the ``translucency = "profile"`` path (:mod:`scenes.subsurface` holds the model
and computes its tables): per image row and run of the object, the :class:`Kernel` of the run's
local geometry (laser ray and view in the surface's frame, and the reference's ray offset) spreads
the opaque stand-in's stripe (:func:`spread_row`, :func:`spread`). Pure numpy; no Mitsuba.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Dict

import numpy as np

if TYPE_CHECKING:
    from .subsurface import LineSpread

__all__ = ["SPREAD_VERSION", "RAY_EPSILON", "Kernel", "local_geometry", "ray_offset_mm", "row_segments",
           "spread_row", "spread"]

#: Version of the kernels and the spreading (:class:`Kernel`, :func:`spread`), in the render cache key of
#: ``translucency = "profile"`` frames: bump it whenever they change their output.
SPREAD_VERSION = 1
#: Mitsuba 3's ``math::RayEpsilon`` for single precision (1500 * 2**-24), the relative offset of spawned rays.
RAY_EPSILON = 1500.0 * 2.0 ** -24
_KEY_STEP = 0.01         # the local directions are rounded to this (about 0.6 deg) before a kernel is made
_SOURCE_FRACTION = 1e-2  # pixels of a run above this fraction of its maximum are spread (the stripe itself)


# -- kernels --------------------------------------------------------------------------------------------------

class Kernel:
    """The line-spread kernel of one local geometry: its CDF in mm and its total.

    Parameters
    ----------
    table : LineSpread
    omega : array_like, shape (3,)
        The laser ray's direction in the local frame ``(b, t, n)``: across the line (towards larger
        ``u``), along it, and **into** the surface (``omega[2] > 0``).
    view : array_like, shape (3,)
        The direction from the surface point to the camera in the same frame (``view[2] > 0``).
    offset_mm : float
        Depth at which the camera ray resumes inside the medium (:func:`ray_offset_mm`; 0 for the
        continuous physics), mm.

    Attributes
    ----------
    total : float
        The kernel's integral: the radiance towards the camera relative to a white Lambertian surface
        under the same line (the directional albedo).
    """

    _MIN_COS = 0.05

    def __init__(self, table: LineSpread, omega, view, offset_mm: float = 0.0):
        spec = table.spec
        ob, _, on = (float(x) for x in omega)
        vb, _, vn = (float(x) for x in view)
        on, vn = max(on, self._MIN_COS), max(vn, self._MIN_COS)
        d = max(float(offset_mm), 0.0) / spec.mfp_mm
        self.mfp_mm = spec.mfp_mm
        a = spec.albedo
        tanv = vb / vn
        # single scattering: exit u = u0 + c t, t ~ Exp(kappa), weight amp
        self._u0 = d * ob / on
        self._c = ob + on * tanv
        self._kappa = 1.0 + on / vn
        self._amp = a / (4.0 * (vn + on)) * math.exp(-d / on)
        # collided: bilinear interpolation between incidence nodes, projection along the view
        m = _interpolate(table, math.degrees(math.atan2(ob, on)), math.hypot(ob, on))
        z = table.z_nodes_mfp
        h = spec.step_mfp
        frac = np.clip((z + 0.5 * h - d) / h, 0.0, 1.0)
        frac[0] = np.clip((0.5 * h - d) / (0.5 * h), 0.0, 1.0)  # the surface node holds the top half cell
        f = frac * np.exp(-np.clip(z - d, 0.0, None) / vn) / (4.0 * vn)
        shift = (z - d) * tanv / h  # in grid steps
        n_u = m.shape[1]
        pos = np.arange(n_u)[None, :] + shift[:, None]
        ip = np.floor(pos)
        t = pos - ip
        w = m * f[:, None]
        ok = (ip >= 0) & (ip < n_u - 1) & (w != 0)
        base = ip[ok].astype(np.int64)
        masses = (np.bincount(base, (w * (1 - t))[ok], n_u) + np.bincount(base + 1, (w * t)[ok], n_u))
        self._edges = (table.u_nodes_mfp[0] - 0.5 * h) + h * np.arange(n_u + 1)
        self._cum = np.concatenate([[0.0], np.cumsum(masses)])
        self.total = float(self._amp + self._cum[-1])

    def cdf(self, x_mm) -> np.ndarray:
        """``integral of k from -inf to x_mm``, vectorised; rises from 0 to :attr:`total`."""
        x = np.asarray(x_mm, float) / self.mfp_mm
        out = np.interp(x, self._edges, self._cum, left=0.0, right=self._cum[-1])
        c, k, u0 = self._c, self._kappa, self._u0
        with np.errstate(over="ignore", invalid="ignore"):
            if abs(c) < 1e-9:
                single = np.where(x >= u0, 1.0, 0.0)
            elif c > 0:
                single = np.where(x >= u0, -np.expm1(-k * (x - u0) / c), 0.0)
            else:
                single = np.where(x <= u0, np.exp(-k * (u0 - x) / -c), 1.0)
        return out + self._amp * single


def _interpolate(table: LineSpread, phi_deg: float, rho: float) -> np.ndarray:
    """Bilinear interpolation of the collided table between incidence nodes (clamped at the ends)."""
    pn = np.asarray(table.spec.phi_nodes_deg, float)
    rn = np.asarray(table.spec.rho_nodes, float)

    def bracket(nodes, x):
        x = min(max(x, nodes[0]), nodes[-1])
        i = int(np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, len(nodes) - 2))
        return i, (x - nodes[i]) / (nodes[i + 1] - nodes[i])

    i, fp = bracket(pn, phi_deg)
    j, fr = bracket(rn, rho)
    c = table.collided
    return ((1 - fp) * (1 - fr) * c[i, j].astype(np.float64) + fp * (1 - fr) * c[i + 1, j]
            + (1 - fp) * fr * c[i, j + 1] + fp * fr * c[i + 1, j + 1])


def ray_offset_mm(points_cm) -> np.ndarray:
    """Mitsuba 3's spawn offset ``(1 + max_i |p_i|) * RayEpsilon`` at world points given in cm (the scenes are
    in metres), mm.

    Examples
    --------
    >>> round(float(ray_offset_mm(np.array([35.0, -8.0, 2.0]))), 4)
    0.1207
    """
    p_m = np.abs(np.asarray(points_cm, float)) * 0.01
    return (1.0 + p_m.max(axis=-1)) * RAY_EPSILON * 1000.0


def local_geometry(point_cm, normal, sheet_normal, laser_origin_cm, camera_cm):
    """The laser ray and the view in the local frame ``(b, t, n)`` of a surface point (see :class:`Kernel`).

    ``n`` is the unit normal turned towards the camera, ``t = sheet_normal x n`` (the line's direction) and
    ``b = t x n``, signed so that ``b . sheet_normal > 0`` (``u`` grows with the signed distance to the sheet).

    Returns
    -------
    omega, view : ndarray, shape (3,)
    """
    p = np.asarray(point_cm, float)
    n = np.asarray(normal, float)
    n = n / np.linalg.norm(n)
    cam = np.asarray(camera_cm, float)
    v = cam - p
    v /= np.linalg.norm(v)
    if n @ v < 0:
        n = -n
    nl = np.asarray(sheet_normal, float)
    t = np.cross(nl, n)
    norm = np.linalg.norm(t)
    t = np.array([0.0, 0.0, 1.0]) if norm < 1e-9 else t / norm
    b = np.cross(t, n)
    if b @ nl < 0:
        b, t = -b, -t
    om = p - np.asarray(laser_origin_cm, float)
    om /= np.linalg.norm(om)
    return np.array([om @ b, om @ t, -(om @ n)]), np.array([v @ b, v @ t, v @ n])


# -- spreading ---------------------------------------------------------------------------------------------------

def row_segments(points_cm: np.ndarray, on_object: np.ndarray, jump: float = 4.0):
    """Runs of one image row that lie on one connected piece of the object.

    A run breaks where the row leaves the object or where neighbouring pixels' surface points are more than
    ``jump`` times the row's median neighbour distance apart (a finger in front of the palm).

    Parameters
    ----------
    points_cm : ndarray, shape (W, 3)
    on_object : ndarray, shape (W,), bool

    Returns
    -------
    list of ndarray
        Column indices of each run, ascending.

    Examples
    --------
    >>> p = np.c_[np.arange(6.0), np.zeros(6), np.zeros(6)]
    >>> p[4:, 1] = 5.0                                   # a step of 5 cm between columns 3 and 4
    >>> [s.tolist() for s in row_segments(p, np.array([1, 1, 1, 1, 1, 0], bool))]
    [[0, 1, 2, 3], [4]]
    """
    ok = np.asarray(on_object, bool) & np.all(np.isfinite(points_cm), axis=-1)
    idx = np.nonzero(ok)[0]
    if idx.size == 0:
        return []
    step = np.linalg.norm(np.diff(points_cm[idx], axis=0), axis=1)
    adjacent = np.diff(idx) == 1
    typical = np.median(step[adjacent]) if adjacent.any() else np.inf
    cut = ~adjacent | (step > jump * typical)
    return np.split(idx, np.nonzero(cut)[0] + 1)


def spread_row(values: np.ndarray, u_mm: np.ndarray, kernel: Kernel, gain: float = 1.0,
               min_fraction: float = _SOURCE_FRACTION) -> np.ndarray:
    """Spread one run of radiance samples along the surface by ``kernel``.

    Each source pixel ``c'`` (radiance above ``min_fraction`` of the run's maximum: the stripe, not the dim
    light the stand-in's interreflections put around it) sends its energy
    ``L(c') du(c')`` to the pixels ``c`` of the run in proportion to the kernel's integral over their
    intervals ``u(c) ± du(c)/2`` relative to ``u(c')``, normalised over the run; the others keep their
    radiance; then the whole run is multiplied by ``gain``. With ``gain = 1`` the energy ``sum L du`` of the
    run is conserved exactly.

    Parameters
    ----------
    values : ndarray, shape (N,)
        Radiance of the run's pixels.
    u_mm : ndarray, shape (N,)
        Their signed distance from the line along the surface, mm (monotone along a smooth run).
    kernel : Kernel
    gain : float
        Energy factor of the spread light (the directional albedo over the stand-in's albedo).

    Returns
    -------
    ndarray, shape (N,), float64
    """
    v = np.asarray(values, float)
    u = np.asarray(u_mm, float)
    if v.size == 0 or not np.any(v > 0):
        return v.copy()
    du = np.abs(np.gradient(u)) if u.size > 1 else np.ones(1)
    du = np.maximum(du, 1e-6 * max(float(np.max(du)), 1e-9))
    src = v > min_fraction * v.max()
    us, es = u[src], v[src] * du[src]
    w = kernel.cdf(u[:, None] + 0.5 * du[:, None] - us[None, :]) - kernel.cdf(u[:, None] - 0.5 * du[:, None] - us[None, :])
    w = np.clip(w, 0.0, None)
    tot = w.sum(axis=0)
    keep = tot <= 0
    w = np.where(keep[None, :], 0.0, w / np.where(keep, 1.0, tot)[None, :])
    out = (w @ es) / du
    out[src] += np.where(keep, v[src], 0.0)  # nowhere to go: stays
    out[~src] += v[~src]
    return out * gain


def spread(laser: np.ndarray, points_cm: np.ndarray, normals: np.ndarray, on_object: np.ndarray, *,
           sheet_normal, laser_origin_cm, camera_cm, table: LineSpread, albedo: float,
           ray_offset: bool = True) -> np.ndarray:
    """The profile path's laser pass: the opaque stripe ``laser`` spread by the local kernels.

    Per image row and run of the object (:func:`row_segments`), the kernel of the run's lit geometry
    (the energy-weighted mean surface point and normal of its source pixels; :func:`local_geometry`,
    :func:`ray_offset_mm`) spreads the run (:func:`spread_row`) with gain ``kernel.total / albedo``.
    Pixels off the object keep their values.

    Parameters
    ----------
    laser : ndarray, shape (H, W)
        The opaque stand-in's laser pass (diffuse BSDF of albedo ``albedo`` on the object).
    points_cm, normals : ndarray, shape (H, W, 3)
        First surface hit through each pixel centre (cm) and its unit shading normal (NaN on misses).
    on_object : ndarray, shape (H, W), bool
    sheet_normal, laser_origin_cm, camera_cm : array_like, shape (3,)
        The laser plane's unit normal (the plane through the origin), the laser pinhole and the camera centre.
    table : LineSpread
    albedo : float
        The stand-in's albedo.
    ray_offset : bool
        Reproduce the reference's ray offset (:func:`ray_offset_mm`); False: the continuous physics.

    Returns
    -------
    ndarray, shape (H, W), float32
    """
    img = np.asarray(laser, np.float64)
    out = img.copy()
    nl = np.asarray(sheet_normal, float)
    cam = np.asarray(camera_cm, float)
    with np.errstate(invalid="ignore"):
        nrm = np.asarray(normals, float)
        facing = np.sum(nrm * (cam - points_cm), axis=-1) < 0
        nrm = np.where(facing[..., None], -nrm, nrm)
        sin_g = np.sqrt(np.clip(1.0 - (nrm @ nl) ** 2, 0.01, 1.0))
        u_all = 10.0 * (points_cm @ nl) / sin_g
    memo: Dict[tuple, Kernel] = {}
    for r in np.nonzero(np.any(on_object & (img > 0), axis=1))[0]:
        for seg in row_segments(points_cm[r], on_object[r]):
            vals = img[r, seg]
            if not np.any(vals > 0):
                continue
            src = vals > _SOURCE_FRACTION * vals.max()
            wts = vals[src]
            p = (points_cm[r, seg][src] * wts[:, None]).sum(0) / wts.sum()
            n = (nrm[r, seg][src] * wts[:, None]).sum(0)
            if not np.all(np.isfinite(n)) or np.linalg.norm(n) == 0:
                continue
            omega, view = local_geometry(p, n, nl, laser_origin_cm, cam)
            off = float(ray_offset_mm(p)) if ray_offset else 0.0
            key = tuple(np.round(np.r_[omega, view] / _KEY_STEP) * _KEY_STEP) + (round(off, 4),)
            kern = memo.get(key)
            if kern is None:
                kern = memo[key] = Kernel(table, key[:3], key[3:6], key[6])
            out[r, seg] = spread_row(vals, u_all[r, seg], kern, gain=kern.total / albedo)
    return out.astype(np.float32)
