"""Sweep curves (pure) and the curve figure, on hand-made tables."""

import itertools

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from bench.run.sweep import Sweep
from bench.report.sweep import curve_figure, curves, per_unit_costs, reference_point

SWEEP = Sweep((("ambient_lux", (0.0, 400.0, 2000.0)), ("laser_power_mw", (1.0, 3.0))), repeats=3)


def _table():
    rows = []
    for (lux, mw), r, tr in itertools.product(itertools.product(*(v for _, v in SWEEP.axes)), range(3),
                                              ("a", "b")):
        # hit rate falls with lux, rises with power; repeat r adds 0.01 * r
        rows.append({"experiment": "cone-patchy", "material": "patchy", "ambient_lux": lux, "laser_power_mw": mw,
                     "repeat": r, "tracker": tr, "hit_rate": 1.0 - lux / 4000 + mw / 100 + 0.01 * r,
                     "depth_rmse_mm": 1.0 + (tr == "b"), "within_5mm": np.nan if tr == "b" else 0.5})
    return pd.DataFrame(rows)


def test_reference_is_the_paper_point_when_swept_else_the_default_else_the_first():
    assert reference_point(SWEEP.to_dict()) == {"ambient_lux": 400.0, "laser_power_mw": 3.0}
    assert reference_point({"exposure_ms": [2.0, 5.0, 8.0], "f_number": [2.0, 8.0]}) == \
        {"exposure_ms": 5.0, "f_number": 2.0}
    assert reference_point({"material": ["matte", "patchy"]}, material="patchy") == {"material": "patchy"}
    assert reference_point({"material": ["matte", "glossy"]}, material="patchy") == {"material": "matte"}


def test_curve_against_lux_holds_power_at_3_mw_with_a_t_interval_over_repeats():
    c = curves(_table(), SWEEP)
    pt = [r for r in c if r["key"] == "ambient_lux" and r["value"] == 2000.0 and r["tracker"] == "a"
          and r["metric"] == "hit_rate"]
    assert len(pt) == 1
    x = np.array([1.0 - 0.5 + 0.03 + 0.01 * r for r in range(3)])
    lo, hi = stats.t.interval(0.95, 2, loc=x.mean(), scale=stats.sem(x))
    assert pt[0]["mean"] == pytest.approx(x.mean()) and pt[0]["n"] == 3
    assert (pt[0]["low"], pt[0]["high"]) == pytest.approx((lo, hi))
    # one record per experiment x key x value x tracker x metric
    assert len(c) == (3 + 2) * 2 * 3


def test_all_nan_metric_gives_nan_and_one_repeat_gives_no_band():
    c = curves(_table(), SWEEP)
    w = [r for r in c if r["tracker"] == "b" and r["metric"] == "within_5mm"]
    assert all(np.isnan(r["mean"]) and r["n"] == 0 for r in w)
    one = curves(_table().query("repeat == 0"), SWEEP)
    assert all(np.isnan(r["low"]) and np.isnan(r["high"]) and r["n"] == 1 for r in one if r["metric"] == "hit_rate")


def test_per_unit_costs_sum_over_units_of_one_size():
    units = [{"width": 64, "height": 60, "frames": 3, "render_s": 4.0, "first_render_s": 2.0, "setup_s": 1.0,
              "evaluations": 30, "eval_s": 3.0},
             {"width": 64, "height": 60, "frames": 3, "render_s": 2.0, "first_render_s": 1.0, "setup_s": 1.0,
              "evaluations": 10, "eval_s": 1.0}]
    (c,) = per_unit_costs(units)
    assert c["render_s_per_frame"] == pytest.approx(1.0) and c["eval_s_per_evaluation"] == pytest.approx(0.1)
    assert c["render_s_per_later_frame"] == pytest.approx(3.0 / 4) and c["units"] == 2


def test_curve_figure_writes_a_png(tmp_path):
    path = curve_figure(curves(_table(), SWEEP), SWEEP.to_dict(), tmp_path / "c.png", title="t")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_docstring_examples():
    import doctest

    import bench.evaluate.curves

    result = doctest.testmod(bench.evaluate.curves, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0
