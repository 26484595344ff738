"""The translucency study: its pieces on synthetic data and a tiny rendered run."""

import csv

import numpy as np
import pytest

from bench.studies import translucency as T


def _main(argv):
    """``stripebench translucency ARGV``."""
    from bench.cli import main

    return main(["translucency", *argv])


def test_stripe_widths_of_a_gaussian_and_of_an_empty_row():
    x = np.arange(61.0)
    sigma = np.array([1.0, 3.0])
    img = np.exp(-0.5 * ((x[None, :] - 30.0) / sigma[:, None]) ** 2)
    img = np.vstack([img, np.zeros(61)])
    fwhm, w1090, peak = T.stripe_widths_px(img, np.array([30.0, 30.0, np.nan]), 25)
    # FWHM = 2.355 sigma (linear interpolation is coarse at sigma = 1 px)
    assert fwhm[1] == pytest.approx(2.3548 * 3.0, rel=0.02)
    assert fwhm[0] == pytest.approx(2.3548, rel=0.1)
    assert w1090[1] == pytest.approx(2.5631 * 3.0, rel=0.02)
    assert peak[:2] == pytest.approx([1.0, 1.0]) and np.isnan(fwhm[2]) and np.isnan(peak[2])


def test_incidence_is_zero_head_on_and_grows_to_grazing():
    from scenes import shapes

    sphere = shapes.uv_sphere(1.0, 96, 48)
    laser = np.array([0.0, -10.0, 0.0])
    pts = np.array([[0.0, -1.0, 0.0], [np.sin(np.radians(60)), -np.cos(np.radians(60)), 0.0], [np.nan] * 3])
    inc = T.incidence_deg(pts, laser, sphere)
    assert inc[0] == pytest.approx(0.0, abs=2.0)
    assert 55.0 < inc[1] < 70.0  # 60 deg normal tilt, seen from a laser 10 radii away
    assert np.isnan(inc[2])


def _record(material, inc, truth, col, peak=1.0):
    return {"object": "plane", "material": material, "mirror_angle_deg": 0.0, "row": 0, "incidence_deg": inc,
            "fwhm_px": 2.0, "width1090_px": 2.5, "peak": peak, "truth_px": truth, "depth_truth_mm": np.nan,
            "com_bg_px": col}


def test_summary_bins_by_incidence_and_signs_depth_farther_positive():
    recs = [_record("matte", 10.0, 200.0, 200.0), _record("matte", 12.0, 210.0, 210.0),
            _record("skin", 11.0, 200.0, 199.0, 0.5), _record("skin", 14.0, 210.0, 209.0, 0.5),
            _record("skin", 40.0, 220.0, np.nan, 0.5)]
    rows = T.summarise(recs, 512)
    by = {(r["material"], r["incidence_lo_deg"]): r for r in rows}
    assert set(by) == {("matte", 0.0), ("skin", 0.0), ("skin", 30.0)}
    m, s = by[("matte", 0.0)], by[("skin", 0.0)]
    assert m["bias_px"] == 0.0 and m["bias_mm"] == 0.0 and m["rows"] == 2 and m["reported"] == 1.0
    assert s["bias_px"] == -1.0 and s["spread_px"] == 0.0
    # a smaller column is a farther point in this rig (R = 20 cm images at column 483, 60 cm at 29)
    assert s["bias_mm"] > 0.0 and s["peak_rel"] == 0.5
    assert by[("skin", 30.0)]["reported"] == 0.0 and np.isnan(by[("skin", 30.0)]["bias_mm"])
    assert np.isnan(by[("skin", 30.0)]["peak_rel"])  # no matte in that bin


@pytest.mark.slow
def test_tiny_study_writes_table_and_plot(tmp_path):
    argv = ["--out", str(tmp_path), "--objects", "plane", "--materials", "matte,skin", "--angles", "1",
            "--size", "64", "--spp", "8", "--trackers", "com_bg,gauss3,threshold", "--quiet"]
    assert _main(argv) == 0
    with open(tmp_path / "translucency.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert tuple(rows[0].keys()) == T.FIELDS
    assert {r["tracker"] for r in rows} == {"com_bg", "gauss3"}  # threshold is not sub-pixel
    assert {r["material"] for r in rows} == {"matte", "skin"}
    fwhm = {}
    for r in rows:
        fwhm.setdefault(r["material"], []).append(float(r["fwhm_px"]) * int(r["rows"]))
    n = {m: sum(int(r["rows"]) for r in rows if r["material"] == m) for m in fwhm}
    assert sum(fwhm["skin"]) / n["skin"] > sum(fwhm["matte"]) / n["matte"]
    assert (tmp_path / "translucency.png").read_bytes()[:4] == b"\x89PNG"


def test_render_noise_falls_with_spp_beside_a_positive_sensor_noise(tmp_path, monkeypatch):
    monkeypatch.setenv("STRIPEBENCH_CACHE_DIR", str(tmp_path))
    rows = T.render_noise("plane", "skin", [2, 32], width=64, height=60, sensor_draws=2)
    assert [r["spp"] for r in rows] == [2, 32] and tuple(rows[0]) == T.NOISE_FIELDS
    for r in rows:
        assert r["rows"] > 8 and r["sensor_noise_px"] > 0 and r["sensor_noise_mad_px"] > 0
        assert r["mc_noise_px"] >= 0 and r["cpu_s_per_frame"] > 0
    assert rows[1]["mc_noise_mad_px"] < rows[0]["mc_noise_mad_px"]  # 16x the samples: less noise


def test_bad_arguments_exit_2(tmp_path, capsys):
    for argv in (["--materials", "velvet"], ["--size", "100"], ["--angles", "0"]):
        with pytest.raises(SystemExit) as exc:
            _main(["--out", str(tmp_path)] + argv)
        assert exc.value.code == 2
    assert "unknown material 'velvet'" in capsys.readouterr().err
    assert _main(["--out", str(tmp_path), "--trackers", "threshold"]) == 2  # checked after parsing, one line
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "none of the selected trackers is a sub-pixel tracker" in err[0]


def test_docstring_examples():
    import doctest

    assert doctest.testmod(T, raise_on_error=False).failed == 0
