"""The paper's precision-improvement statistic with bootstrap confidence intervals."""

from __future__ import annotations

import numpy as np

__all__ = ["spread", "improvement", "bootstrap_improvement", "STATISTICS"]

STATISTICS = ("rmse", "mae", "std")


def spread(errors, statistic: str = "rmse") -> float:
    """RMSE, MAE or standard deviation of ``errors`` (NaNs are an error)."""
    e = np.asarray(errors, dtype=np.float64)
    if np.isnan(e).any():
        raise ValueError("`errors` must not contain NaN")
    if statistic == "rmse":
        return float(np.sqrt(np.mean(e * e)))
    if statistic == "mae":
        return float(np.mean(np.abs(e)))
    if statistic == "std":
        return float(np.std(e, ddof=1)) if e.size > 1 else float("nan")
    raise ValueError(f"`statistic` must be one of {STATISTICS}, got {statistic!r}")


def improvement(errors_dp, errors_base, statistic: str = "rmse") -> float:
    """``1 - S(errors_dp) / S(errors_base)``: the paper's "30 % more precise".

    Positive when DP's errors are smaller. Both arrays are errors at the same
    sample points (paired).
    """
    a = np.asarray(errors_dp, dtype=np.float64)
    b = np.asarray(errors_base, dtype=np.float64)
    if a.shape != b.shape or a.ndim != 1:
        raise ValueError(f"`errors_dp` and `errors_base` must be 1-D of one length, got {a.shape} and {b.shape}")
    base = spread(b, statistic)
    if base == 0:
        return float("nan")
    return 1.0 - spread(a, statistic) / base


def bootstrap_improvement(errors_dp, errors_base, statistic: str = "rmse", *, n_boot: int = 2000, seed: int = 0,
                          level: float = 0.95) -> dict[str, float]:
    """The improvement and its percentile bootstrap confidence interval.

    Samples are resampled in pairs (the same points for both trackers), with
    ``numpy.random.default_rng(seed)``.

    Returns
    -------
    dict with ``value``, ``low``, ``high``, ``level``, ``n``, ``n_boot``.
    """
    a = np.asarray(errors_dp, dtype=np.float64)
    b = np.asarray(errors_base, dtype=np.float64)
    value = improvement(a, b, statistic)
    n = a.size
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, n, size=(n_boot, n))
    A, B = a[idx], b[idx]
    if statistic == "rmse":
        sa, sb = np.sqrt((A * A).mean(1)), np.sqrt((B * B).mean(1))
    elif statistic == "mae":
        sa, sb = np.abs(A).mean(1), np.abs(B).mean(1)
    else:
        sa, sb = A.std(1, ddof=1), B.std(1, ddof=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        boots = 1.0 - sa / sb
    boots = boots[np.isfinite(boots)]
    alpha = (1.0 - level) / 2.0
    low, high = (np.quantile(boots, [alpha, 1 - alpha]) if boots.size else (np.nan, np.nan))
    return {"value": value, "low": float(low), "high": float(high), "level": level, "n": int(n), "n_boot": int(n_boot)}
