"""From image column and row to 3-D points: the paper's eqs (3), (4) and (7).

At mirror angle ``theta`` a stripe pixel (column ``u``, row ``v``) has sensor
coordinates ``P_x = rig.px_mm(u)``, ``P_z = rig.pz_mm(v)`` (mm), and

* eq. (3): ``R = (f delta_0 - P_x d_m) / (f sin zeta + P_x cos zeta)``,
* eq. (4): ``phi = 2 theta - zeta``,
* eq. (7): ``Z = P_z (delta_0 - R sin zeta) / P_x``,

in the rig's cylindrical coordinates about the mirror axis (cm, degrees);
the Cartesian point is ``(R sin phi, R cos phi, Z)``. Where ``P_x`` is 0
(the column of ``R = delta_0 / sin zeta``), eq. (7) is 0/0; there the
algebraically identical form ``Z = P_z (d_m + R cos zeta) / f`` (eq. (5)
divided by eq. (2) rearranged) is used. Pure functions of arrays; any shape.
"""

from __future__ import annotations

import numpy as np

from scenes.rig import cylindrical_to_cartesian  # one home: the rig's geometry

__all__ = ["triangulate", "depth_cm", "points_from_depth", "cylindrical_to_cartesian"]

_PX_TINY_MM = 1e-9


def _rig_numbers(rig):
    f = float(rig.focal_mm) / 10.0  # mm -> cm, so every length is in cm
    return f, float(rig.d_m_cm), float(rig.delta0_cm), np.radians(float(rig.zeta_deg))


def depth_cm(cols, rig) -> np.ndarray:
    """Eq. (3): distance ``R`` (cm) from the mirror axis of the stripe seen at column(s) ``cols``.

    Independent of the row and of the mirror angle (the paper notes the
    mirror angle is not involved). NaN columns give NaN.
    """
    f, d_m, delta0, zeta = _rig_numbers(rig)
    px = np.asarray(rig.px_mm(np.asarray(cols, dtype=np.float64)), dtype=np.float64) / 10.0
    with np.errstate(divide="ignore", invalid="ignore"):
        return (f * delta0 - px * d_m) / (f * np.sin(zeta) + px * np.cos(zeta))


def triangulate(cols, rows, mirror_angle_deg, rig):
    """Cylindrical coordinates of stripe pixels.

    Parameters
    ----------
    cols, rows : array_like
        Continuous column and row indices (pixel centre at integer values),
        broadcast together; NaN columns give NaN outputs.
    mirror_angle_deg : float or array_like
        Mirror angle theta (deg), broadcast with ``cols``.
    rig : scenes.Rig
        Provides ``px_mm``, ``pz_mm``, ``focal_mm``, ``d_m_cm``,
        ``delta0_cm``, ``zeta_deg``.

    Returns
    -------
    r_cm, phi_deg, z_cm : ndarray
        Eqs. (3), (4), (7).
    """
    cols, rows, theta = np.broadcast_arrays(
        np.asarray(cols, dtype=np.float64), np.asarray(rows, dtype=np.float64),
        np.asarray(mirror_angle_deg, dtype=np.float64),
    )
    f, d_m, delta0, zeta = _rig_numbers(rig)
    px = np.asarray(rig.px_mm(cols), dtype=np.float64) / 10.0
    pz = np.asarray(rig.pz_mm(rows), dtype=np.float64) / 10.0
    with np.errstate(divide="ignore", invalid="ignore"):
        r = (f * delta0 - px * d_m) / (f * np.sin(zeta) + px * np.cos(zeta))
        z7 = pz * (delta0 - r * np.sin(zeta)) / px
        z5 = pz * (d_m + r * np.cos(zeta)) / f
    z = np.where(np.abs(px) > _PX_TINY_MM / 10.0, z7, z5)
    phi = 2.0 * theta - np.degrees(zeta)
    phi = np.where(np.isnan(r), np.nan, phi)
    return r, phi, z


def points_from_depth(r_cm, rows, mirror_angle_deg, rig) -> np.ndarray:
    """World points (cm), shape (..., 3), of depths ``R`` seen on image ``rows`` at a mirror angle.

    For restored surfaces, where a filled row has a depth but no column: ``phi``
    from eq. (4) and ``Z`` from eq. (5) with ``d_r = R cos(zeta)`` (the form of
    eq. (7) that needs no column). NaN depths give NaN points.
    """
    r, rows, theta = np.broadcast_arrays(np.asarray(r_cm, dtype=np.float64), np.asarray(rows, dtype=np.float64),
                                         np.asarray(mirror_angle_deg, dtype=np.float64))
    f, d_m, _, zeta = _rig_numbers(rig)
    pz = np.asarray(rig.pz_mm(rows), dtype=np.float64) / 10.0
    z = pz * (d_m + r * np.cos(zeta)) / f
    phi = 2.0 * theta - np.degrees(zeta)
    return cylindrical_to_cartesian(r, phi, z)
