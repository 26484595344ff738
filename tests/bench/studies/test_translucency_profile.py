"""The profile-vs-volpath study: its measurements on synthetic rows and a tiny rendered run."""

import csv

import numpy as np
import pytest

from bench.studies import translucency_profile as P
from bench.cli.translucency_profile import main as _main  # python -m bench.cli.translucency_profile


def _gauss_rows(n, centres, sigma, width=81):
    x = np.arange(float(width))
    return np.exp(-0.5 * ((x[None, :] - np.asarray(centres, float)[:, None]) / sigma) ** 2)


def test_centres_find_a_gaussian_peak_and_its_centroid():
    img = _gauss_rows(2, [40.25, 39.8], 2.5)
    par, core, win = P.centres(img, np.array([40.0, 40.0]), np.array([0, 1]), 15)
    assert par == pytest.approx([40.25, 39.8], abs=0.05) and win == pytest.approx([40.25, 39.8], abs=1e-3)
    assert core == pytest.approx([40.25, 39.8], abs=0.05)
    # a tail on one side moves the window's centroid, hardly the core's
    tail = img + 0.05 * (np.arange(81.0) > 40)[None, :]
    _, core_t, win_t = P.centres(tail, np.array([40.0, 40.0]), np.array([0, 1]), 15)
    assert win_t[0] - win[0] > 4 * abs(core_t[0] - core[0])


def test_aligned_width_undoes_the_noise_bias_of_a_single_rows_fwhm():
    from bench.studies.translucency import stripe_widths_px

    rng = np.random.default_rng(6)
    n, sigma = 60, 3.0
    truth = 40.0 + rng.uniform(-0.4, 0.4, n)
    clean = _gauss_rows(n, truth, sigma)
    noisy = clean + rng.normal(0.0, 0.15, clean.shape)
    rows = np.arange(n)
    true_fwhm = 2.3548 * sigma
    single, _, _ = stripe_widths_px(noisy, truth, 20)
    aligned = P.aligned_fwhm(noisy, truth, rows, 20)
    assert np.median(single) < 0.95 * true_fwhm  # noise raises the maximum: a narrower half width
    assert np.median(aligned) == pytest.approx(true_fwhm, rel=0.04)
    assert np.median(P.aligned_fwhm(clean, truth, rows, 20, n_rows=1)) == pytest.approx(true_fwhm, rel=0.03)


def test_median_difference_and_its_interval():
    rng = np.random.default_rng(2)
    a = rng.normal(1.0, 0.5, 400)
    d, lo, hi = P._median_diff_ci(a, a + 0.1, 500, 0)
    assert d == pytest.approx(0.1) and lo == pytest.approx(0.1) and hi == pytest.approx(0.1)
    b = a + rng.normal(0.0, 0.3, 400)
    d, lo, hi = P._median_diff_ci(a, b, 500, 0)
    assert lo < d < hi and hi - lo < 0.2


def _path(bias, fwhm, z, s):
    n = 50
    return {"parabolic_mm": np.full(n, bias), "core_mm": np.full(n, bias), "window_mm": np.full(n, bias),
            "theta_deg": np.repeat([0.0, 1.0], n // 2), "fwhm_px": np.full(n, fwhm), "fwhm_matched_px": np.full(n, fwhm),
            "frames": 2, "jump_rows": 0, "z_pixel": z, "render_noise_px": z * 0.1, "sensor_noise_px": 0.1, "z": z, "z_robust": z, "s_per_frame": s,
            "cpu_s_per_frame": s, "first_s": s, "rendered": 2, "laser_energy": 1.0, "ambient_mean": 1.0}


@pytest.mark.parametrize("profile,ok", [
    (_path(0.93, 10.2, 0.1, 1.0), (True, True, True)),
    (_path(1.00, 10.2, 0.1, 1.0), (False, True, True)),   # 0.07 mm off
    (_path(0.93, 10.9, 1.2, 1.0), (True, False, False)),  # 9 % wider, noisier than the sensor
])
def test_compare_applies_the_issues_criteria(profile, ok):
    lines, c, angles = P.compare("plane", "skin", {"volpath": _path(0.93, 10.0, 3.0, 8.0), "profile": profile, "rows": 50})
    assert [r["path"] for r in lines] == ["volpath", "profile"] and set(c) == set(P.COMPARE_FIELDS)
    assert [a["mirror_angle_deg"] for a in angles] == [0.0, 1.0] and set(angles[0]) == set(P.ANGLE_FIELDS)
    assert (c["bias_ok"], c["width_ok"], c["noise_ok"]) == ok
    assert c["cost_ratio"] == pytest.approx(8.0)


@pytest.mark.slow
def test_tiny_study_writes_both_tables(tmp_path):
    argv = ["--out", str(tmp_path), "--objects", "plane", "--angles", "1", "--size", "64", "--quiet"]
    assert _main(argv) == 0
    with open(tmp_path / "paths.csv") as fh:
        paths = list(csv.DictReader(fh))
    with open(tmp_path / "comparison.csv") as fh:
        comp = list(csv.DictReader(fh))
    assert tuple(paths[0]) == P.PATH_FIELDS and [r["path"] for r in paths] == ["volpath", "profile"]
    assert tuple(comp[0]) == P.COMPARE_FIELDS and len(comp) == 1
    assert all(float(r["s_per_frame"]) > 0 and float(r["sensor_noise_px"]) > 0 for r in paths)
    assert float(comp[0]["bias_volpath_mm"]) > 0  # skin is seen farther than its surface


def test_bad_arguments_exit_2(tmp_path, capsys):
    for argv, message in ((["--materials", "matte"], "unknown material 'matte'"),
                          (["--seeds", "1"], "argument --seeds: must be two different integers"),
                          (["--size", "100"], "must be a multiple of 16")):
        with pytest.raises(SystemExit) as exc:
            _main(["--out", str(tmp_path)] + argv)
        assert exc.value.code == 2
        assert message in capsys.readouterr().err


def test_docstring_examples():
    import doctest

    assert doctest.testmod(P, raise_on_error=False).failed == 0
