import numpy as np
import pytest

from bench.evaluate.stats import bootstrap_improvement, bootstrap_mean, improvement, mad_scale, spread, t_interval


def test_spread():
    e = np.array([3.0, -4.0])
    assert spread(e, "rmse") == pytest.approx(np.sqrt(12.5))
    assert spread(e, "mae") == pytest.approx(3.5)
    assert spread(e, "std") == pytest.approx(np.std(e, ddof=1))
    with pytest.raises(ValueError, match="`statistic` must be one of"):
        spread(e, "median")
    with pytest.raises(ValueError, match="must not contain NaN"):
        spread([np.nan], "rmse")


def test_improvement_is_the_papers_statistic():
    base = np.array([1.0, -1.0, 1.0, -1.0])
    assert improvement(0.7 * base, base) == pytest.approx(0.3)
    assert improvement(2 * base, base) == pytest.approx(-1.0)
    with pytest.raises(ValueError, match="one length"):
        improvement(np.ones(3), np.ones(4))


def test_bootstrap_ci_brackets_the_value_and_is_seeded():
    rng = np.random.default_rng(0)
    base = rng.normal(0, 3, 150)
    dp = rng.normal(0, 2, 150)
    a = bootstrap_improvement(dp, base, "rmse", n_boot=500, seed=1)
    b = bootstrap_improvement(dp, base, "rmse", n_boot=500, seed=1)
    assert a == b
    assert a["low"] < a["value"] < a["high"] and a["n"] == 150
    c = bootstrap_improvement(dp, base, "rmse", n_boot=500, seed=2)
    assert c["low"] != a["low"]


def test_bootstrap_covers_the_true_improvement_usually():
    # two error distributions with a known RMSE ratio: the 95 % CI should
    # contain 1 - 2/3 in most seeded repetitions
    hits = 0
    for seed in range(40):
        rng = np.random.default_rng(100 + seed)
        base = rng.normal(0, 3, 150)
        dp = rng.normal(0, 2, 150)
        ci = bootstrap_improvement(dp, base, "rmse", n_boot=400, seed=seed)
        hits += ci["low"] <= 1 / 3 <= ci["high"]
    assert hits >= 32


def test_wilson_interval_by_hand():
    from bench.evaluate.stats import wilson_interval

    # k = 8, n = 10, z = 1.96: centre (0.8 + z^2/20) / (1 + z^2/10) = 0.7167,
    # half-width z sqrt(0.016 + z^2/400) / (1 + z^2/10) = 0.2266 (the textbook [0.490, 0.943])
    lo, hi = wilson_interval(8, 10)
    assert lo == pytest.approx(0.4902, abs=1e-4) and hi == pytest.approx(0.9433, abs=1e-4)
    assert wilson_interval(0, 5)[0] == 0.0 and wilson_interval(5, 5)[1] == 1.0
    assert all(np.isnan(wilson_interval(0, 0)))


def test_robust_summary_by_hand():
    from bench.evaluate.stats import robust_summary

    e = [1.0, -2.0, 7.0, -80.0, np.nan, 5.0, 51.0]
    r = robust_summary(e)
    assert r["n"] == 6 and r["within"] == pytest.approx(3 / 6)  # 1, 2, 5 (the band is closed)
    assert r["median_abs_mm"] == pytest.approx(6.0) and r["n_gross"] == 2
    assert r["median_mm"] == pytest.approx(3.0)  # signed: median of -80, -2, 1, 5, 7, 51
    assert r["p95_abs_mm"] == pytest.approx(np.percentile([1, 2, 5, 7, 51, 80], 95))
    assert r["rmse_mm"] == pytest.approx(np.sqrt(np.mean(np.square([1, 2, 5, 7, 51, 80]))))
    assert r["within_low"] < 0.5 < r["within_high"]
    assert robust_summary([np.nan])["n"] == 0


def test_bootstrap_mean_is_seeded_and_brackets_the_mean():
    v = [0.2, 0.9, 0.5, 0.7, np.nan, 0.1]
    a = bootstrap_mean(v, n_boot=500, seed=3)
    assert a == bootstrap_mean(v, n_boot=500, seed=3)
    assert a["n"] == 5 and a["mean"] == pytest.approx(0.48)
    assert 0.1 <= a["lo"] < a["mean"] < a["hi"] <= 0.9
    assert bootstrap_mean(v, n_boot=500, seed=4) != a


def test_t_interval_by_hand():
    # mean 2, s = 1, n = 3: half-width t(0.975, 2) * 1 / sqrt(3) = 4.302653 / 1.732051
    m, lo, hi = t_interval(np.array([1.0, 2.0, 3.0, np.nan]))
    assert m == 2.0 and hi - m == pytest.approx(4.302653 / np.sqrt(3), rel=1e-6) and m - lo == pytest.approx(hi - m)
    assert np.isnan(t_interval(np.array([5.0]))[1]) and np.isnan(t_interval(np.array([np.nan]))[0])


def test_mad_scale_ignores_one_outlier():
    assert mad_scale(np.array([-1.0, 0.0, 1.0, 100.0])) == pytest.approx(1.4826)
    assert mad_scale(np.zeros(5)) == 0.0 and np.isnan(mad_scale(np.array([np.nan])))
