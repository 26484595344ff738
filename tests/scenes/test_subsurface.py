"""The line-spread profile of the translucent materials: the table's file, its kernels, the spreading."""

import dataclasses
import math

import numpy as np
import pytest

from scenes import subsurface as S


def _small(material="skin", **change):
    small = dict(photons=2048, u_max_mfp=12.0, z_max_mfp=6.0, step_mfp=0.2,
                 phi_nodes_deg=(-60.0, -30.0, 0.0, 30.0, 60.0), rho_nodes=(0.5, 1.0))
    return dataclasses.replace(S.spec_for(material), **{**small, **change})


@pytest.fixture(scope="module")
def table():
    return S.compute(_small(photons=8192))


def test_spec_refuses_bad_values():
    with pytest.raises(ValueError, match=r"`albedo` must be in \[0, 1\], got 1.5"):
        dataclasses.replace(S.spec_for("wax"), albedo=1.5)
    with pytest.raises(ValueError, match="`photons` must be an integer >= 1, got 0"):
        dataclasses.replace(S.spec_for("wax"), photons=0)
    with pytest.raises(KeyError, match="translucent materials skin, marble, wax, got 'matte'"):
        S.spec_for("matte")


def test_profile_file_round_trip_and_refusal_of_another_version(table, tmp_path):
    path = S.write(table, tmp_path / "skin.npz")
    back = S.read(path)
    assert back.spec == table.spec and back.diffuse_reflectance == table.diffuse_reflectance
    assert back.collided.dtype == np.float32 and np.array_equal(back.collided, table.collided)
    arrays = table.to_arrays()
    arrays["format_version"] = np.array(S.FORMAT_VERSION + 1)
    np.savez(tmp_path / "future.npz", **arrays)
    with pytest.raises(ValueError, match=rf"future.npz has profile format version {S.FORMAT_VERSION + 1}, "
                                         rf"this stripebench reads version {S.FORMAT_VERSION}"):
        S.read(tmp_path / "future.npz")
    del arrays["format_version"]
    with pytest.raises(ValueError, match="not a line-spread profile file"):
        S.LineSpread.from_arrays(arrays)
    arrays = {**table.to_arrays(), "collided": table.collided[:, :, :-1]}
    with pytest.raises(ValueError, match="`collided` has shape"):
        S.LineSpread.from_arrays(arrays)


def test_the_table_is_a_pure_function_of_its_spec():
    spec = _small(photons=512)
    a, b = S.compute(spec), S.compute(spec)
    assert np.array_equal(a.collided, b.collided) and a.diffuse_reflectance == b.diffuse_reflectance
    c = S.compute(dataclasses.replace(spec, seed=spec.seed + 1))
    assert not np.array_equal(a.collided, c.collided)


def test_table_for_caches_the_table_on_disk_and_recomputes_a_damaged_file(tmp_path, monkeypatch, capsys):
    from scenes import cache as C

    spec = _small("wax", photons=256)
    monkeypatch.setattr(S, "spec_for", lambda m: spec)
    monkeypatch.setattr(S, "_MEMORY", {})
    first = S.table_for("wax", tmp_path)
    files = list((tmp_path / "profiles").rglob("*.npz"))
    assert len(files) == 1
    monkeypatch.setattr(S, "_MEMORY", {})
    monkeypatch.setattr(S, "compute", lambda spec: pytest.fail("recomputed a cached table"))
    assert np.array_equal(S.table_for("wax", tmp_path).collided, first.collided)
    # an entry of another format version under the key: reported and recomputed
    k = C.key(spec.key_fields())
    arrays = {**first.to_arrays(), "format_version": np.array(0)}
    C.store(tmp_path / "profiles", k, arrays)
    monkeypatch.setattr(S, "_MEMORY", {})
    monkeypatch.setattr(S, "compute", lambda spec: first)
    S.table_for("wax", tmp_path)
    assert "profile format version 0" in capsys.readouterr().err


def _chandrasekhar_table(d=0.0):
    """A table without collided light (one collision): the kernel is the analytic single scattering."""
    return S.compute(_small(max_collisions=1, photons=64))


@pytest.mark.parametrize("offset_mfp", [0.0, 0.3])
def test_single_scattering_is_chandrasekhars_with_the_ray_offset(offset_mfp):
    t = _chandrasekhar_table()
    assert not t.collided.any()
    om = np.array([-0.4, 0.1, 0.0])
    om[2] = math.sqrt(1 - om[0] ** 2 - om[1] ** 2)
    v = np.array([0.3, -0.2, 0.0])
    v[2] = math.sqrt(1 - v[0] ** 2 - v[1] ** 2)
    k = S.Kernel(t, om, v, offset_mm=offset_mfp * t.spec.mfp_mm)
    a = t.spec.albedo
    assert k.total == pytest.approx(a / (4 * (om[2] + v[2])) * math.exp(-offset_mfp / om[2]), rel=1e-12)
    # the mean exit point: u0 = offset omega_b / omega_n, then s (omega_b + omega_n v_b / v_n) with
    # s ~ Exp(1 + omega_n / v_n), in mean free paths
    x = np.linspace(-20, 20, 400001) * t.spec.mfp_mm
    dens = np.diff(k.cdf(x))
    mean_mm = float(np.sum(0.5 * (x[1:] + x[:-1]) * dens) / dens.sum())
    c = om[0] + om[2] * v[0] / v[2]
    expect = offset_mfp * om[0] / om[2] + c / (1 + om[2] / v[2])
    assert mean_mm / t.spec.mfp_mm == pytest.approx(expect, abs=1e-3)


def _direct_mc(spec, om, v, n=40000, seed=3):
    """An independent light tracer for one geometry (no table, no node interpolation): total and mean exit u."""
    rng = np.random.default_rng(seed)
    a, thick = spec.albedo, spec.slab_thickness_mm * spec.sigma_t_per_mm
    pos = rng.exponential(1.0, n)[:, None] * np.asarray(om)[None, :]
    w = np.ones(n)
    alive = pos[:, 2] < thick
    tot, mom = 0.0, 0.0
    for _ in range(spec.max_collisions):
        z = pos[:, 2]
        c = np.where(alive, w * a * np.exp(-z / v[2]) / (4 * v[2]), 0.0)
        tot += c.sum()
        mom += (c * (pos[:, 0] + z * v[0] / v[2])).sum()
        w = w * a
        mu = rng.uniform(-1, 1, n)
        ph = rng.uniform(0, 2 * np.pi, n)
        d = np.stack([np.sqrt(1 - mu * mu) * np.cos(ph), np.sqrt(1 - mu * mu) * np.sin(ph), mu], 1)
        pos = pos + rng.exponential(1.0, n)[:, None] * d
        alive &= (pos[:, 2] > 0) & (pos[:, 2] < thick)
    return tot / n, mom / tot


@pytest.mark.parametrize("phi_deg,view_deg", [(0.0, -13.0), (-25.0, 12.0), (40.0, -38.0), (15.0, 5.0)])
def test_kernel_agrees_with_a_direct_light_tracer(table, phi_deg, view_deg):
    # off the nodes too (15 deg): the bilinear interpolation between incidence nodes
    om = np.array([math.sin(math.radians(phi_deg)), 0.0, math.cos(math.radians(phi_deg))])
    v = np.array([math.sin(math.radians(view_deg)), 0.0, math.cos(math.radians(view_deg))])
    total, mean = _direct_mc(table.spec, om, v)
    k = S.Kernel(table, om, v)
    x = np.linspace(-table.spec.u_max_mfp, table.spec.u_max_mfp, 20001) * table.spec.mfp_mm
    dens = np.diff(k.cdf(x))
    kmean = float(np.sum(0.5 * (x[1:] + x[:-1]) * dens) / dens.sum()) / table.spec.mfp_mm
    assert k.total == pytest.approx(total, rel=0.03)
    assert kmean == pytest.approx(mean, abs=0.06)  # mean free paths


def _gauss_run(n=121, step=0.2, centre=0.13, sigma=0.47):
    u = (np.arange(n) - n // 2) * step * (1 + 0.002 * np.arange(n))  # a slightly foreshortened row
    return u, np.exp(-0.5 * ((u - centre) / sigma) ** 2)


def test_spreading_conserves_the_runs_energy_and_widens_the_stripe(table):
    u, v = _gauss_run()
    k = S.Kernel(table, (0.0, 0.0, 1.0), (-0.22, 0.0, 0.975))
    du = np.abs(np.gradient(u))
    out = S.spread_row(v, u, k)
    assert np.sum(out * du) == pytest.approx(np.sum(v * du), rel=1e-12)
    assert np.all(out >= 0) and out.max() < 0.8 * v.max()
    var = lambda y: np.sum(y * du * u ** 2) / np.sum(y * du) - (np.sum(y * du * u) / np.sum(y * du)) ** 2
    assert var(out) > 2 * var(v)
    assert np.sum(S.spread_row(v, u, k, gain=0.5) * du) == pytest.approx(0.5 * np.sum(v * du), rel=1e-12)
    # a run whose light has nowhere to go keeps it; an empty run stays empty
    assert np.array_equal(S.spread_row(np.zeros(5), u[:5], k), np.zeros(5))


def test_spread_leaves_pixels_off_the_object_alone(table):
    u, v = _gauss_run(n=64)
    h = 3
    laser = np.tile(v, (h, 1)).astype(np.float32)
    pts = np.zeros((h, 64, 3))
    pts[..., 0] = u / 10.0  # cm, the sheet is x = 0
    pts[..., 1] = 30.0
    pts[:, :, 2] = np.arange(h)[:, None] * 0.02
    nrm = np.broadcast_to([0.0, -1.0, 0.0], pts.shape)
    on = np.ones((h, 64), bool)
    on[1] = False
    out = S.spread(laser, pts, nrm, on, sheet_normal=[1.0, 0.0, 0.0], laser_origin_cm=[0.0, -10.0, 0.0],
                   camera_cm=[-8.0, -15.0, 0.0], table=table, albedo=table.diffuse_reflectance)
    assert out.dtype == np.float32 and np.array_equal(out[1], laser[1])
    assert not np.allclose(out[0], laser[0]) and np.array_equal(out[0], out[2])


def test_local_frame_faces_the_camera_and_follows_the_sheet():
    om, v = S.local_geometry([0.0, 30.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, -10.0, 0.0], [-8.0, -15.0, 0.0])
    assert om[2] == pytest.approx(1.0) and v[2] > 0.9 and v[0] < 0  # the camera is on the -x side
    assert np.linalg.norm(om) == pytest.approx(1.0) and np.linalg.norm(v) == pytest.approx(1.0)


def test_ray_offset_is_mitsubas_spawn_offset():
    from scenes import variant

    mi = variant.mitsuba()
    p_cm = np.array([12.0, 34.0, -3.0])
    si = mi.SurfaceInteraction3f()
    si.p = mi.Point3f(*(float(x) for x in p_cm * 0.01))
    si.n = mi.Normal3f(0.0, -1.0, 0.0)
    o = si.spawn_ray(mi.Vector3f(0.0, 1.0, 0.0)).o
    offset_m = float(np.array(o.y).ravel()[0]) - 0.34
    assert S.RAY_EPSILON == pytest.approx(float(mi.math.RayEpsilon), rel=1e-7)
    assert float(S.ray_offset_mm(p_cm)) == pytest.approx(1000.0 * offset_m, rel=1e-3)
