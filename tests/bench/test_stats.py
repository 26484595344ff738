import numpy as np
import pytest

from bench.stats import bootstrap_improvement, improvement, spread


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
