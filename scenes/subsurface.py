"""The ``translucency = "profile"`` path: a line-spread profile of a translucent medium, applied to the
opaque stripe in image space.

A laser line on a translucent surface glows: light enters along the sheet, scatters under the surface
and leaves around the line. With the materials' index-matched (``null``) boundary and isotropic
scattering (:data:`scenes.materials.PHASE_G` = 0), the radiance a camera sees at a surface point is the
line integral, along the camera ray inside the medium, of ``albedo / (4 pi)`` times the collision density
of the light; that density depends on the medium, the slab and the direction the light came in, not on
the camera. This module computes it once per material by Monte Carlo (a light tracer from the laser:
every path starts in the sheet, so it converges where the camera-side ``volpath`` is noisiest) and, per
image row, projects it along the local view direction into a **line-spread kernel** ``k(u)``: the
radiance at signed distance ``u`` (mm, on the surface, across the line; positive towards increasing
image column) from a line of unit irradiance-per-length, relative to a white Lambertian surface under
the same line. The laser pass of a translucent material is then the opaque stripe (a diffuse BSDF of
the material's :attr:`LineSpread.diffuse_reflectance`, path traced) spread along each image row by the
kernel of the row's local geometry (:func:`scenes.spreading.spread`).

The model (in mean free paths ``l = 1 / sigma_t``, half-space of depth ``z`` below the surface, closed by
the slab's back face at :data:`scenes.description.SLAB_THICKNESS_CM`):

* single scattering, analytic: light entering along ``omega`` (local components ``omega_b`` across the
  line, ``omega_n`` into the surface) first collides at ``s ~ Exp(1)``; seen by the camera along ``v``
  (``v_b``, ``v_n`` out of the surface) at ``u = s (omega_b + omega_n v_b / v_n)`` with weight
  ``albedo exp(-s omega_n / v_n) / (4 v_n)`` (Chandrasekhar's single-scattering reflectance,
  ``albedo / (4 (omega_n + v_n))`` in total);
* two and more collisions, tabulated: the emission-weighted collision density ``albedo^k`` of
  collisions ``k = 2 .. K`` in the cross-section ``(u, z)``, for incidence nodes
  (:data:`PHI_NODES_DEG`: the in-section angle ``atan2(omega_b, omega_n)``; :data:`RHO_NODES`: the
  in-section speed ``hypot(omega_b, omega_n)``), bilinearly interpolated between nodes and projected
  along ``v`` with the transmittance ``exp(-z / v_n)``;
* ``K`` = :data:`scenes.materials.MEDIUM_MAX_DEPTH` - 1 = 63: ``volpath`` estimates the light at a
  medium scattering only while its depth counter (one per medium scattering, none at a ``null``
  interface) is below ``max_depth``;
* **the reference's ray offset.** Mitsuba 3 spawns the ray that continues through a ``null`` interface
  ``(1 + max |p|) * RayEpsilon`` along the surface normal (``p`` in scene units, metres here;
  ``RayEpsilon`` = 1500 * 2**-24): about 0.12 mm at the rig's 0.3-0.4 m. ``volpath``'s camera ray
  therefore resumes inside the medium 0.12 mm below the surface point it crossed, parallel to itself:
  it skips the top 0.12 mm of the medium (its single-scattered laser light is
  ``exp(-0.12 mm sigma_t / omega_n)`` of Chandrasekhar's, 0.77 for marble at normal incidence) and sees the
  sheet displaced by ``0.12 mm * omega_b / omega_n`` across the line (measured by
  ``python -m bench.studies.translucency_profile --single-scatter``). The kernel reproduces it
  (``offset_mm`` of :class:`scenes.spreading.Kernel`, from each row's own surface point), because ``volpath`` is the
  reference this path is validated against (docs/translucency.md).

Pure numpy; no Mitsuba. The tables are a pure function of their :class:`ProfileSpec` (its seed included)
and live in the render cache folder under ``profiles/`` (:func:`table_for`), one ``.npz`` per spec in
the versioned format of :meth:`LineSpread.to_arrays`. The kernels and the spreading are in
:mod:`scenes.spreading` (their names are importable from here too).
"""

from __future__ import annotations

import dataclasses
import math
import os
import sys
from pathlib import Path
from typing import Dict, Optional, Tuple

import numpy as np

from . import cache as _cache, materials
# the kernels and the spreading (scenes.spreading), here too: the profile path's public names stay in one place
from .spreading import (RAY_EPSILON, SPREAD_VERSION, Kernel, local_geometry, ray_offset_mm, row_segments, spread,
                        spread_row)

__all__ = ["FORMAT_VERSION", "SPREAD_VERSION", "RAY_EPSILON", "PHI_NODES_DEG", "RHO_NODES", "ProfileSpec", "spec_for", "LineSpread",
           "compute", "table_for", "read", "write", "Kernel", "local_geometry", "ray_offset_mm", "row_segments",
           "spread_row", "spread"]

#: Version of the profile file format (:meth:`LineSpread.to_arrays`); a file of another version is refused.
FORMAT_VERSION = 1
#: Incidence nodes of the collided table: in-section angle ``atan2(omega_b, omega_n)``, deg.
PHI_NODES_DEG = tuple(float(a) for a in range(-80, 81, 10))
#: Incidence nodes: in-section speed ``hypot(omega_b, omega_n)`` (1: the laser ray lies in the
#: cross-section; smaller: it runs partly along the line).
RHO_NODES = (0.25, 0.5, 0.75, 1.0)
_PHOTONS = 32768
_CHUNK = 4096
_SEED = 20240601
_GRID_MFP = 0.1          # grid step of the table in u and z, mean free paths
_Z_MAX_MFP = 10.0        # deepest emission tabulated (exp(-10) of the surface's)
_U_MAX_MFP = 20.0        # half-width of the table, at least; at least two diffusion lengths too
_FORMAT_KEY = "format_version"


@dataclasses.dataclass(frozen=True)
class ProfileSpec:
    """Everything a :class:`LineSpread` table depends on (its cache key).

    Attributes
    ----------
    sigma_t_per_mm : float
        Extinction ``sigma_s' + sigma_a`` of the rendered medium (g = 0), mm⁻¹.
    albedo : float
        Single-scattering albedo ``sigma_s / sigma_t``.
    slab_thickness_mm : float
        Depth of the slab (its back face lets light out), mm.
    max_collisions : int
        Collisions whose light reaches the camera, ``MEDIUM_MAX_DEPTH - 1``.
    photons : int
        Monte Carlo paths per incidence node (the same paths for every node).
    seed : int
        Seed of the paths (``numpy.random.PCG64``).
    u_max_mfp, z_max_mfp, step_mfp : float
        Table extent across the line (±), in depth, and its step, mean free paths.
    phi_nodes_deg, rho_nodes : tuple of float
        The incidence nodes (:data:`PHI_NODES_DEG`, :data:`RHO_NODES`).
    """

    sigma_t_per_mm: float
    albedo: float
    slab_thickness_mm: float
    max_collisions: int
    photons: int = _PHOTONS
    seed: int = _SEED
    u_max_mfp: float = _U_MAX_MFP
    z_max_mfp: float = _Z_MAX_MFP
    step_mfp: float = _GRID_MFP
    phi_nodes_deg: Tuple[float, ...] = PHI_NODES_DEG
    rho_nodes: Tuple[float, ...] = RHO_NODES

    def __post_init__(self):
        for name in ("sigma_t_per_mm", "slab_thickness_mm", "u_max_mfp", "z_max_mfp", "step_mfp"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ValueError(f"`{name}` must be a finite number > 0, got {v!r}")
        if isinstance(self.albedo, bool) or not isinstance(self.albedo, (int, float)) or not 0 <= self.albedo <= 1:
            raise ValueError(f"`albedo` must be in [0, 1], got {self.albedo!r}")
        for name in ("max_collisions", "photons"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise ValueError(f"`{name}` must be an integer >= 1, got {v!r}")
        if len(self.phi_nodes_deg) < 2 or len(self.rho_nodes) < 2:
            raise ValueError(f"`phi_nodes_deg` and `rho_nodes` need two nodes or more, got {self.phi_nodes_deg!r}, "
                             f"{self.rho_nodes!r}")

    @property
    def mfp_mm(self) -> float:
        """Mean free path ``1 / sigma_t``, mm."""
        return 1.0 / self.sigma_t_per_mm

    def key_fields(self) -> dict:
        """The fields of the table's cache key (with the format version)."""
        return {"kind": "line_spread_profile", _FORMAT_KEY: FORMAT_VERSION,
                **{k: (list(v) if isinstance(v, tuple) else v) for k, v in dataclasses.asdict(self).items()}}


def spec_for(material: str, slab_thickness_cm: Optional[float] = None) -> ProfileSpec:
    """The :class:`ProfileSpec` of a translucent ``material`` as ``volpath`` renders it.

    Examples
    --------
    >>> s = spec_for("skin")
    >>> round(s.sigma_t_per_mm, 3), round(s.albedo, 4), s.slab_thickness_mm, s.max_collisions
    (0.772, 0.9585, 20.0, 63)
    """
    from .description import SLAB_THICKNESS_CM

    t = materials.TRANSLUCENT.get(material)
    if t is None:
        raise KeyError(f"`material` must be one of the translucent materials {', '.join(materials.TRANSLUCENT)}, "
                       f"got {material!r}")
    if materials.PHASE_G != 0.0:
        raise ValueError(f"the profile model needs isotropic scattering (materials.PHASE_G = 0), got {materials.PHASE_G!r}")
    slab = SLAB_THICKNESS_CM if slab_thickness_cm is None else slab_thickness_cm
    return ProfileSpec(sigma_t_per_mm=float(t.sigma_t_reduced_per_mm), albedo=float(t.albedo_reduced),
                       slab_thickness_mm=10.0 * float(slab), max_collisions=materials.MEDIUM_MAX_DEPTH - 1,
                       u_max_mfp=max(_U_MAX_MFP, 2.0 * t.diffusion_length_mm * t.sigma_t_reduced_per_mm))


@dataclasses.dataclass(frozen=True)
class LineSpread:
    """A material's line-spread table (see the module docstring).

    Attributes
    ----------
    spec : ProfileSpec
    collided : ndarray, shape (n_phi, n_rho, n_z, n_u), float32
        Emission-weighted density of collisions 2 .. K per unit incident line power, per node of the
        grid ``z = i * step``, ``u = -u_max + j * step`` (mean free paths; cloud-in-cell weights).
    diffuse_reflectance : float
        The total diffuse reflectance: the fraction of normally incident light the slab sends back through
        its front face within ``max_collisions`` collisions (Monte Carlo; Jensen et al. 2001's ``R_d``
        without their diffusion approximation). The albedo of the opaque stand-in in both passes: under
        the uniform sky a surface sends ``R_dh(v)``, the directional-hemispherical reflectance of its view
        direction (reciprocity), which this is at normal view.
    """

    spec: ProfileSpec
    collided: np.ndarray
    diffuse_reflectance: float

    @property
    def u_nodes_mfp(self) -> np.ndarray:
        """Across-line grid nodes, mean free paths."""
        n = self.collided.shape[-1]
        return -self.spec.u_max_mfp + self.spec.step_mfp * np.arange(n)

    @property
    def z_nodes_mfp(self) -> np.ndarray:
        """Depth grid nodes, mean free paths."""
        return self.spec.step_mfp * np.arange(self.collided.shape[-2])

    def to_arrays(self) -> Dict[str, np.ndarray]:
        """The arrays of the profile file: ``format_version``, ``spec`` (JSON of :meth:`ProfileSpec.key_fields`),
        ``collided``, ``diffuse_reflectance``."""
        import json

        return {_FORMAT_KEY: np.array(FORMAT_VERSION, np.int64),
                "spec": np.array(json.dumps(self.spec.key_fields(), sort_keys=True)),
                "collided": np.ascontiguousarray(self.collided, np.float32),
                "diffuse_reflectance": np.array(float(self.diffuse_reflectance))}

    @classmethod
    def from_arrays(cls, arrays: Dict[str, np.ndarray], source: str = "profile") -> "LineSpread":
        """Inverse of :meth:`to_arrays`.

        Raises
        ------
        ValueError
            ``source`` has another format version, lacks an array or holds a table of the wrong shape.
        """
        import json

        if _FORMAT_KEY not in arrays:
            raise ValueError(f"{source} has no `{_FORMAT_KEY}`: not a line-spread profile file")
        version = int(np.asarray(arrays[_FORMAT_KEY]))
        if version != FORMAT_VERSION:
            raise ValueError(f"{source} has profile format version {version}, this stripebench reads version "
                             f"{FORMAT_VERSION}")
        missing = sorted({"spec", "collided", "diffuse_reflectance"} - set(arrays))
        if missing:
            raise ValueError(f"{source} lacks {', '.join(missing)}")
        fields = json.loads(str(arrays["spec"]))
        fields.pop("kind", None)
        fields.pop(_FORMAT_KEY, None)
        spec = ProfileSpec(**{k: (tuple(v) if isinstance(v, list) else v) for k, v in fields.items()})
        collided = np.asarray(arrays["collided"], np.float32)
        shape = _grid_shape(spec)
        if collided.shape != shape:
            raise ValueError(f"{source}: `collided` has shape {collided.shape}, its spec needs {shape}")
        return cls(spec, collided, float(arrays["diffuse_reflectance"]))


def write(table: LineSpread, path: os.PathLike) -> Path:
    """Write ``table`` to ``path`` (``.npz``, :meth:`LineSpread.to_arrays`); returns the path."""
    path = Path(path)
    with open(path, "wb") as fh:
        np.savez(fh, **table.to_arrays())
    return path


def read(path: os.PathLike) -> LineSpread:
    """Read a profile file written by :func:`write`.

    Raises
    ------
    ValueError
        Another format version, or not a profile file (the message names the file).
    """
    with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    return LineSpread.from_arrays(arrays, source=f"profile file {path}")


def _grid_shape(spec: ProfileSpec) -> Tuple[int, int, int, int]:
    n_u = 2 * int(round(spec.u_max_mfp / spec.step_mfp)) + 1
    n_z = int(round(spec.z_max_mfp / spec.step_mfp)) + 1
    return len(spec.phi_nodes_deg), len(spec.rho_nodes), n_z, n_u


def _isotropic(rng, shape):
    mu = rng.uniform(-1.0, 1.0, shape)
    ph = rng.uniform(0.0, 2.0 * np.pi, shape)
    return np.sqrt(1.0 - mu * mu) * np.cos(ph), mu  # across-line and depth components


def compute(spec: ProfileSpec) -> LineSpread:
    """Run the Monte Carlo of a :class:`ProfileSpec` (a few seconds; deterministic for a spec).

    The same ``photons`` random walks (after their first collision) serve every incidence node: a walk
    placed with its first collision at the node's ``(u1, z1) = s rho (sin phi, cos phi)`` (``s`` the
    walk's stratified Exp(1) quantile) keeps the collisions that precede its first exit through the
    front or the back face.
    """
    ss = np.random.SeedSequence(spec.seed)
    rng_walk, rng_sky = (np.random.Generator(np.random.PCG64(s)) for s in ss.spawn(2))
    n_phi, n_rho, n_z, n_u = _grid_shape(spec)
    h = spec.step_mfp
    thick = spec.slab_thickness_mm * spec.sigma_t_per_mm
    a = spec.albedo
    k_after = spec.max_collisions - 1  # collisions 2 .. K
    phi = np.radians(np.asarray(spec.phi_nodes_deg, float))
    rho = np.asarray(spec.rho_nodes, float)
    acc = np.zeros((n_phi * n_rho, n_z * n_u))
    weights = a ** np.arange(2, spec.max_collisions + 1, dtype=float)  # emission weight of collision k
    size = n_z * n_u
    for start in range(0, spec.photons, _CHUNK):
        m = min(_CHUNK, spec.photons - start)
        j = np.arange(start, start + m, dtype=float)
        s = -np.log1p(-(j + 0.5) / spec.photons)  # stratified first flights, Exp(1)
        if k_after < 1:
            continue
        flights = rng_walk.exponential(1.0, (m, k_after))
        db, dz = _isotropic(rng_walk, (m, k_after))
        pu = np.cumsum(flights * db, axis=1)
        pz = np.cumsum(flights * dz, axis=1)
        lo = np.minimum.accumulate(pz, axis=1)
        hi = np.maximum.accumulate(pz, axis=1)
        w = np.broadcast_to(weights, pu.shape)
        for i_p, ph in enumerate(phi):
            for i_r, r in enumerate(rho):
                z1 = (s * r * math.cos(ph))[:, None]
                u1 = (s * r * math.sin(ph))[:, None]
                z = z1 + pz
                alive = (z1 + lo > 0.0) & (z1 + hi < thick) & (z1 < thick) & (z < spec.z_max_mfp)
                fz = z / h
                fu = (u1 + pu + spec.u_max_mfp) / h
                iz = np.floor(fz)
                iu = np.floor(fu)
                ok = alive & (iu >= 0) & (iu < n_u - 1) & (iz >= 0)
                tz, tu = (fz - iz)[ok], (fu - iu)[ok]
                base = (iz[ok] * n_u + iu[ok]).astype(np.int64)
                ww = w[ok]
                node = acc[i_p * n_rho + i_r]
                node += np.bincount(base, ww * (1 - tz) * (1 - tu), size)
                node += np.bincount(base + 1, ww * (1 - tz) * tu, size)
                top = iz[ok] < n_z - 1
                node += np.bincount(base[top] + n_u, (ww * tz * (1 - tu))[top], size)
                node += np.bincount(base[top] + n_u + 1, (ww * tz * tu)[top], size)
    collided = (acc / spec.photons).reshape(n_phi, n_rho, n_z, n_u).astype(np.float32)
    return LineSpread(spec, collided, _diffuse_reflectance(spec, rng_sky))


def _diffuse_reflectance(spec: ProfileSpec, rng) -> float:
    """Front-face escape of normally incident light within ``max_collisions`` collisions."""
    n = spec.photons
    thick = spec.slab_thickness_mm * spec.sigma_t_per_mm
    z = rng.exponential(1.0, n)
    alive = z < thick
    w = np.ones(n)
    out = 0.0
    for _ in range(spec.max_collisions):
        w = w * spec.albedo  # scattered at this collision
        _, mu = _isotropic(rng, n)
        z_next = z + rng.exponential(1.0, n) * mu
        out += float(np.sum(w[alive & (z_next <= 0.0)]))
        alive &= (z_next > 0.0) & (z_next < thick)
        z = z_next
    return out / n


_MEMORY: Dict[str, LineSpread] = {}


def table_for(material: str, cache_dir: Optional[os.PathLike] = None, *, use_cache: bool = True) -> LineSpread:
    """The :class:`LineSpread` table of ``material``: from memory, else the profile cache, else computed
    (and stored when ``use_cache``).

    The file is ``<render cache root>/profiles/<key[:2]>/<key>.npz`` (:func:`scenes.cache.cache_root`), the
    key a hash of :meth:`ProfileSpec.key_fields`; a file that is unreadable, damaged or of another format
    version is reported in one line on stderr and recomputed.
    """
    spec = spec_for(material)
    k = _cache.key(spec.key_fields())
    if k in _MEMORY:
        return _MEMORY[k]
    root = _cache.cache_root(cache_dir) / "profiles"
    table = None
    if use_cache:
        arrays = _cache.load(root, k)
        if arrays is not None:
            try:
                table = LineSpread.from_arrays(arrays, source=f"profile cache entry {_cache.path(root, k)}")
            except ValueError as exc:
                print(f"stripebench: {exc}: recomputing", file=sys.stderr)
    if table is None:
        table = compute(spec)
        if use_cache:
            _cache.store(root, k, table.to_arrays())
    _MEMORY[k] = table
    return table
