"""Geometry of the rotating-mirror rig: every pose, ray and transform lives here.

World frame (cm)
----------------
* ``Z`` is the mirror axis, pointing up; the origin is on the mirror axis at the
  height of the camera's optical axis.
* Angles in the top view are measured **clockwise from +Y seen from above**
  (the paper's ``phi``): a point at cylindrical ``(R, phi, Z)`` is
  ``(R sin phi, R cos phi, Z)``.

The mirror is not rendered
--------------------------
A delta light seen through a perfect mirror cannot be path traced, so the mirror
is replaced by its exact equivalent: at mirror angle ``theta`` the *virtual*
camera and the laser sheet rotate together by ``2 theta`` about ``Z``.  At
``theta`` (degrees):

* optical axis ``a = (sin 2θ, cos 2θ, 0)``, lateral unit ``l = (-cos 2θ, sin 2θ, 0)``
  (``l = Z x a``, the camera's left), camera centre ``C = -d_m a + delta_0 l``,
  camera up ``+Z``; the principal point is the image centre.
* laser sheet: the vertical plane through the ``Z`` axis that contains
  ``e_L = cos ζ a + sin ζ l = (sin(2θ-ζ), cos(2θ-ζ), 0)``, so a lit point has
  ``phi = 2θ - ζ`` (paper eq. 4).  A point ``T = R e_L + Z ẑ`` has depth
  ``D = d_m + R cos ζ`` along the optical axis and lateral offset
  ``δ_T = δ_0 - R sin ζ`` (paper eq. 2), and images at
  ``P_x = f δ_T / D``, ``P_z = f Z / D`` (mm).
* The laser source (a pinhole projector) sits on the ``Z = 0`` plane behind the
  axis at ``-d_laser e_L`` (``laser_distance_cm``, default 10 cm), aimed along
  ``e_L``; its fan is vertical, its thin profile horizontal.

Image convention and the mirror flip
------------------------------------
Column ``u`` counts from the left, row ``v`` from the top, and the centre of pixel
``(u, v)`` is at continuous image position ``(u + 0.5, v + 0.5)``.  Sensor
coordinates are ``px_mm(u) = (u + 0.5 - W/2) pitch_x`` (positive to the right,
i.e. along ``-l``: the side *away* from the laser) and
``pz_mm(v) = (H/2 - (v + 0.5)) pitch_y`` (positive up).  This is the image of a
camera placed at the virtual (mirrored) position looking at the world directly;
it is the same convention Mitsuba's ``perspective`` sensor uses with
``look_at(C, C + a, Z)`` (verified by ``tests/scenes/test_rig.py``).  A real camera
looking at the scene *through* the mirror records this image flipped
left-right (a reflection reverses handedness): the real image column is
``W - 1 - u``.  The paper's equations use ``P_x`` as drawn in its Fig. 1,
which is this (virtual-camera) convention.

Choice of ζ, f and pitch
------------------------
``ζ`` solves ``P_x(R=20 cm) = -P_x(R=60 cm)`` (objects 20-60 cm from the axis are
symmetric about the principal point): ``ζ ≈ 14.12°``.  With a 512 x 480 sensor
of 10 µm square pixels (5.12 x 4.80 mm, a 1/2-inch-class CCD) and ``f = 25 mm``,
``R = 20`` lands at column ≈ 482.8 (94 % of the width) and ``R = 60`` at ≈ 29.2
(6 %).  ``R = δ_0 / sin ζ ≈ 32.8 cm`` images at ``P_x = 0`` where the paper's
eq. (7) is 0/0.  The vertical field is ``±(4.8/2)/25 = ±0.096 D``: about
±4.4 cm at ``D = 46 cm`` (``R = 32``) and ±5.2 cm at ``D = 54 cm``
(``R = 40``); objects are therefore about 8-9 cm tall.  Depth resolution
``dR/du`` is ≈ 0.4 mm/px at 20 cm, 1.0 mm/px at 40 cm, 1.9 mm/px at 60 cm.

``width``/``height`` change the pixel count over the *same* field of view
(the pitch scales).  Mitsuba's perspective sensor only has square pixels, so
:func:`scenes.params` insists on ``pitch_x == pitch_y`` when rendering
(e.g. 64x60, 128x120, 256x240, 512x480); the rig maths itself does not care.

Everything here is float64 numpy and vectorised over ``theta`` and points.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Tuple

import numpy as np

__all__ = [
    "Rig",
    "symmetric_zeta_deg",
    "DEFAULT_ZETA_DEG",
    "cylindrical_to_cartesian",
    "rotation_z",
    "rotation_x",
    "translation",
    "scaling",
    "look_at",
    "apply_transform",
    "transform_normals",
    "CM_TO_M",
]

CM_TO_M = 0.01


def symmetric_zeta_deg(d_m_cm: float = 15.0, delta0_cm: float = 8.0,
                       r_near_cm: float = 20.0, r_far_cm: float = 60.0) -> float:
    """Laser angle ζ (deg) that images ``r_near_cm`` and ``r_far_cm`` symmetrically.

    Solves ``P_x(R_near) = -P_x(R_far)`` with ``P_x ∝ (δ_0 - R sin ζ)/(d_m + R cos ζ)``
    (paper eq. 2) by bisection on ``ζ ∈ (0°, 90°)``.

    Parameters
    ----------
    d_m_cm, delta0_cm : float
        Camera distance behind the mirror axis and lateral offset (cm).
    r_near_cm, r_far_cm : float
        Nearest and farthest distances from the mirror axis (cm), ``0 < near < far``.

    Returns
    -------
    float
        ζ in degrees.
    """
    if not 0 < r_near_cm < r_far_cm:
        raise ValueError(f"need 0 < `r_near_cm` < `r_far_cm`, got {r_near_cm!r}, {r_far_cm!r}")

    def g(z: float) -> float:
        s, c = math.sin(z), math.cos(z)
        return ((delta0_cm - r_near_cm * s) / (d_m_cm + r_near_cm * c)
                + (delta0_cm - r_far_cm * s) / (d_m_cm + r_far_cm * c))

    lo, hi = 0.0, math.pi / 2 - 1e-9
    if g(lo) * g(hi) > 0:
        raise ValueError("no symmetric ζ exists for these rig dimensions")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(lo) * g(mid) <= 0:
            hi = mid
        else:
            lo = mid
    return math.degrees(0.5 * (lo + hi))


DEFAULT_ZETA_DEG = symmetric_zeta_deg()


# ----------------------------------------------------------------------------
# small transform helpers (4x4, float64)
# ----------------------------------------------------------------------------

def cylindrical_to_cartesian(r_cm, phi_deg, z_cm) -> np.ndarray:
    """``(R, phi, Z)`` -> ``(R sin phi, R cos phi, Z)``; phi clockwise from +Y (deg). Shape (..., 3)."""
    r, p, z = np.broadcast_arrays(np.asarray(r_cm, float), np.radians(phi_deg), np.asarray(z_cm, float))
    return np.stack([r * np.sin(p), r * np.cos(p), z], axis=-1)


def translation(v) -> np.ndarray:
    """4x4 translation by ``v`` (3,)."""
    m = np.eye(4)
    m[:3, 3] = np.asarray(v, float)
    return m


def scaling(s) -> np.ndarray:
    """4x4 (possibly anisotropic) scaling by ``s`` (scalar or (3,))."""
    m = np.eye(4)
    m[:3, :3] = np.diag(np.broadcast_to(np.asarray(s, float), (3,)))
    return m


def rotation_z(phi_deg: float) -> np.ndarray:
    """4x4 rotation by ``phi_deg`` **clockwise seen from above** about +Z (the rig's angle sense).

    It maps +Y to ``(sin phi, cos phi, 0)``.
    """
    p = math.radians(phi_deg)
    c, s = math.cos(p), math.sin(p)
    m = np.eye(4)
    m[:2, :2] = [[c, s], [-s, c]]
    return m


def rotation_x(angle_deg: float) -> np.ndarray:
    """4x4 right-handed rotation by ``angle_deg`` about +X (tilts +Y towards +Z)."""
    p = math.radians(angle_deg)
    c, s = math.cos(p), math.sin(p)
    m = np.eye(4)
    m[1:3, 1:3] = [[c, -s], [s, c]]
    return m


def look_at(origin, target, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """4x4 camera-to-world matrix with Mitsuba's ``look_at`` convention.

    Local +Z is the viewing direction, local +Y the (orthogonalised) up vector and
    local +X = up x forward (the viewer's *left*).  Same units as ``origin``.
    """
    o = np.asarray(origin, float)
    fwd = np.asarray(target, float) - o
    fwd /= np.linalg.norm(fwd)
    left = np.cross(np.asarray(up, float), fwd)
    left /= np.linalg.norm(left)
    new_up = np.cross(fwd, left)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = left, new_up, fwd, o
    return m


def apply_transform(matrix: np.ndarray, points) -> np.ndarray:
    """Apply a 4x4 affine ``matrix`` to points (..., 3)."""
    p = np.asarray(points, float)
    return p @ matrix[:3, :3].T + matrix[:3, 3]


def transform_normals(matrix: np.ndarray, normals) -> np.ndarray:
    """Transform normals (..., 3) by the inverse transpose of ``matrix``; renormalised."""
    n = np.asarray(normals, float) @ np.linalg.inv(matrix[:3, :3])
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    return n / np.where(norm > 0, norm, 1.0)


def _unit(theta_deg, offset_deg=0.0):
    t = np.radians(2.0 * np.asarray(theta_deg, float) - offset_deg)
    return np.sin(t), np.cos(t)


# ----------------------------------------------------------------------------
# the rig
# ----------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True)
class Rig:
    """The camera, laser and mirror geometry (cm, mm, degrees; float64).

    Parameters
    ----------
    d_m_cm : float
        Distance of the (virtual) camera centre behind the mirror axis, along the optical axis.
    delta0_cm : float
        Lateral offset of the camera centre (along ``l``, the camera's left).
    zeta_deg : float
        Angle between the optical axis and the laser direction (paper's ζ).
    focal_mm : float
        Focal length.
    sensor_width_mm, sensor_height_mm : float
        Active sensor area; fixed when ``width``/``height`` change.
    width, height : int
        Pixel counts.
    laser_distance_cm : float
        Distance of the laser's pinhole behind the mirror axis, along ``-e_L``.
    """

    d_m_cm: float = 15.0
    delta0_cm: float = 8.0
    zeta_deg: float = DEFAULT_ZETA_DEG
    focal_mm: float = 25.0
    sensor_width_mm: float = 5.12
    sensor_height_mm: float = 4.80
    width: int = 512
    height: int = 480
    laser_distance_cm: float = 10.0

    # -- sensor ------------------------------------------------------------
    @property
    def pitch_x_mm(self) -> float:
        """Horizontal pixel pitch (mm): ``sensor_width_mm / width``."""
        return self.sensor_width_mm / self.width

    @property
    def pitch_y_mm(self) -> float:
        """Vertical pixel pitch (mm): ``sensor_height_mm / height``."""
        return self.sensor_height_mm / self.height

    @property
    def fov_x_deg(self) -> float:
        """Full horizontal field of view (deg)."""
        return math.degrees(2.0 * math.atan(0.5 * self.sensor_width_mm / self.focal_mm))

    def with_size(self, width: int, height: int) -> "Rig":
        """The same rig and field of view with ``width`` x ``height`` pixels."""
        return dataclasses.replace(self, width=int(width), height=int(height))

    def px_mm(self, cols) -> np.ndarray:
        """Sensor x (mm, right positive) of continuous column index ``cols`` (pixel centre at ``col + 0.5``)."""
        return (np.asarray(cols, float) + 0.5 - 0.5 * self.width) * self.pitch_x_mm

    def pz_mm(self, rows) -> np.ndarray:
        """Sensor z (mm, up positive) of continuous row index ``rows`` (pixel centre at ``row + 0.5``)."""
        return (0.5 * self.height - (np.asarray(rows, float) + 0.5)) * self.pitch_y_mm

    def col_of_px(self, px_mm) -> np.ndarray:
        """Inverse of :meth:`px_mm`."""
        return np.asarray(px_mm, float) / self.pitch_x_mm + 0.5 * self.width - 0.5

    def row_of_pz(self, pz_mm) -> np.ndarray:
        """Inverse of :meth:`pz_mm`."""
        return 0.5 * self.height - 0.5 - np.asarray(pz_mm, float) / self.pitch_y_mm

    # -- poses ---------------------------------------------------------------
    def optical_axis(self, theta_deg) -> np.ndarray:
        """Unit optical axis ``a = (sin 2θ, cos 2θ, 0)``, shape (..., 3)."""
        s, c = _unit(theta_deg)
        return np.stack([s, c, np.zeros_like(s)], axis=-1)

    def lateral_axis(self, theta_deg) -> np.ndarray:
        """Unit lateral axis ``l = (-cos 2θ, sin 2θ, 0)`` (camera's left), shape (..., 3)."""
        s, c = _unit(theta_deg)
        return np.stack([-c, s, np.zeros_like(s)], axis=-1)

    def camera_center_cm(self, theta_deg) -> np.ndarray:
        """Virtual camera centre ``C = -d_m a + δ_0 l`` (cm), shape (..., 3)."""
        return -self.d_m_cm * self.optical_axis(theta_deg) + self.delta0_cm * self.lateral_axis(theta_deg)

    def laser_direction(self, theta_deg) -> np.ndarray:
        """Unit laser direction ``e_L = (sin(2θ-ζ), cos(2θ-ζ), 0)``, shape (..., 3)."""
        s, c = _unit(theta_deg, self.zeta_deg)
        return np.stack([s, c, np.zeros_like(s)], axis=-1)

    def laser_phi_deg(self, theta_deg) -> np.ndarray:
        """Azimuth ``phi = 2θ - ζ`` of the lit half-plane (paper eq. 4), degrees."""
        return 2.0 * np.asarray(theta_deg, float) - self.zeta_deg

    def laser_origin_cm(self, theta_deg) -> np.ndarray:
        """Laser pinhole ``-d_laser e_L`` (cm), shape (..., 3)."""
        return -self.laser_distance_cm * self.laser_direction(theta_deg)

    def laser_plane(self, theta_deg) -> Tuple[np.ndarray, np.ndarray]:
        """The laser sheet as ``(point_cm, unit_normal)``, each shape (..., 3).

        The point is the origin (the plane contains the Z axis).  The normal is
        ``n = (cos(2θ-ζ), -sin(2θ-ζ), 0) = e_L x Z``; at ``θ = 0`` it points to
        ``+X``, towards increasing image column, so the signed distance
        ``n · (p - point)`` grows from left to right across the stripe on a
        surface that faces the camera.
        """
        s, c = _unit(theta_deg, self.zeta_deg)
        normal = np.stack([c, -s, np.zeros_like(s)], axis=-1)
        return np.zeros_like(normal), normal

    # -- projection ----------------------------------------------------------
    def pixel_rays(self, cols, rows, theta_deg) -> Tuple[np.ndarray, np.ndarray]:
        """Rays through continuous pixel positions (pixel centre of ``(u, v)`` is ``(u+0.5, v+0.5)``).

        Parameters
        ----------
        cols, rows : array_like
            Continuous column / row indices (broadcast together).
        theta_deg : float
            Mirror angle (a scalar).

        Returns
        -------
        origins_cm : ndarray, shape (..., 3)
            The camera centre, broadcast.
        unit_dirs : ndarray, shape (..., 3)
            Unit directions ``∝ f a - P_x l + P_z ẑ``.
        """
        cols, rows = np.broadcast_arrays(np.asarray(cols, float), np.asarray(rows, float))
        a = self.optical_axis(theta_deg)
        lat = self.lateral_axis(theta_deg)
        px = self.px_mm(cols)[..., None]
        pz = self.pz_mm(rows)[..., None]
        d = self.focal_mm * a - px * lat + pz * np.array([0.0, 0.0, 1.0])
        d = d / np.linalg.norm(d, axis=-1, keepdims=True)
        o = np.broadcast_to(self.camera_center_cm(theta_deg), d.shape).copy()
        return o, d

    def sensor_coords_mm(self, points_cm, theta_deg) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(P_x, P_z, D)`` of points (..., 3): sensor mm and depth along the optical axis (cm)."""
        rel = np.asarray(points_cm, float) - self.camera_center_cm(theta_deg)
        depth = rel @ self.optical_axis(theta_deg)
        lateral = -(rel @ self.lateral_axis(theta_deg))
        return self.focal_mm * lateral / depth, self.focal_mm * rel[..., 2] / depth, depth

    def project(self, points_cm, theta_deg) -> Tuple[np.ndarray, np.ndarray]:
        """Continuous ``(cols, rows)`` of world points (..., 3) seen at mirror angle ``theta_deg``."""
        px, pz, _ = self.sensor_coords_mm(points_cm, theta_deg)
        return self.col_of_px(px), self.row_of_pz(pz)

    def intersect_laser_plane(self, origins_cm, dirs, theta_deg) -> Tuple[np.ndarray, np.ndarray]:
        """Float64 intersection of rays with the laser sheet.

        Returns
        -------
        points_cm : ndarray, shape (..., 3)
        t_cm : ndarray, shape (...)
            Ray parameter (distance for unit ``dirs``); NaN for rays parallel to the plane.
        """
        point, normal = self.laser_plane(theta_deg)
        o = np.asarray(origins_cm, float)
        d = np.asarray(dirs, float)
        den = d @ normal
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(den != 0, ((point - o) @ normal) / den, np.nan)
        return o + t[..., None] * d, t

    # -- the paper's eq. (3) -----------------------------------------------------
    def depth_of_column_cm(self, cols) -> np.ndarray:
        """Paper eq. (3): distance ``R`` (cm) from the mirror axis of a lit point seen at column(s) ``cols``.

        ``R = (f δ_0 - P_x d_m) / (f sin ζ + P_x cos ζ)`` with ``P_x = px_mm(cols)``; independent of the
        row and of the mirror angle.  Columns past the vanishing column of the sheet (``P_x = -f tan ζ``,
        far outside any image here) give negative or infinite values.

        Parameters
        ----------
        cols : array_like
            Continuous column indices (pixel centre at integer values), any shape.

        Returns
        -------
        ndarray, float64, same shape as ``cols``
            ``R`` in cm.

        Examples
        --------
        >>> round(float(Rig().depth_of_column_cm(255.5)), 2)  # the principal point: R = δ_0 / sin ζ
        32.79
        """
        f = self.focal_mm / 10.0  # mm -> cm
        px = self.px_mm(cols) / 10.0
        z = math.radians(self.zeta_deg)
        with np.errstate(divide="ignore", invalid="ignore"):
            return (f * self.delta0_cm - px * self.d_m_cm) / (f * math.sin(z) + px * math.cos(z))

    def imaged_range_cm(self, *, edges: bool = False) -> Tuple[float, float]:
        """``(R_min, R_max)`` (cm): the distances from the mirror axis the rig images (eq. 3).

        ``R_min`` is seen at the last column (``width - 1``), ``R_max`` at column 0 (the laser sheet
        sweeps from right to left as ``R`` grows).  A lit point nearer than ``R_min`` or farther than
        ``R_max`` is outside the image whatever the mirror angle.

        Parameters
        ----------
        edges : bool
            False: the centres of the outermost columns; True: the image's outer edges (columns
            ``-0.5`` and ``width - 0.5``), the strict limits.

        Returns
        -------
        tuple of float
            ``(R_min, R_max)`` in cm.

        Examples
        --------
        >>> [round(r, 1) for r in Rig().imaged_range_cm()]
        [18.8, 65.8]
        >>> [round(r, 1) for r in Rig().imaged_range_cm(edges=True)]
        [18.8, 65.9]
        """
        half = 0.5 if edges else 0.0
        r = self.depth_of_column_cm(np.array([self.width - 1 + half, -half]))
        return float(r[0]), float(r[1])

    # -- Mitsuba poses (metres) ----------------------------------------------
    def camera_to_world_m(self, theta_deg: float) -> np.ndarray:
        """4x4 camera-to-world matrix in metres for Mitsuba's ``perspective`` sensor."""
        c = self.camera_center_cm(theta_deg)
        return look_at(c * CM_TO_M, (c + self.optical_axis(theta_deg)) * CM_TO_M)

    def laser_to_world_m(self, theta_deg: float) -> np.ndarray:
        """4x4 projector-to-world matrix in metres (aimed along ``e_L``, up ``+Z``)."""
        o = self.laser_origin_cm(theta_deg)
        return look_at(o * CM_TO_M, (o + self.laser_direction(theta_deg)) * CM_TO_M)
