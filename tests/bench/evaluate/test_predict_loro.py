"""The prediction judged leave one rig out against the null prediction (bench.evaluate.predict_loro), on small sets of
rigs with a planted one."""

import numpy as np
import pandas as pd
import pytest

from bench.evaluate import predict_loro as pl

TRACKERS = ["a", "b", "c", "d"]
RIGS = ["r1", "r2", "r3", "r4", "planted"]


def _tables(planted_error: float = 0.01):
    """Measured F1 per rig and tracker: ``a`` best on four rigs, ``b`` best on the planted one, where ``a`` falls to
    0.6; the method within 0.01 of every figure but one of the planted rig's, off by ``planted_error``."""
    f1 = np.array([[0.95, 0.85, 0.80, 0.70],
                   [0.94, 0.86, 0.82, 0.72],
                   [0.96, 0.84, 0.81, 0.69],
                   [0.95, 0.87, 0.79, 0.71],
                   [0.60, 0.93, 0.80, 0.70]])
    rng = np.random.default_rng(3)
    off = rng.choice([-0.01, 0.01], size=f1.shape)
    off[4, 3] = planted_error
    frr = np.full_like(f1, 0.05)
    measured = {"f1": f1, "hit_rate": f1, "false_report_rate": frr}
    predicted = {"f1": f1 + off, "hit_rate": f1 + off, "false_report_rate": frr + 0.3}  # false reports far too high
    return predicted, measured


def test_the_planted_rig_is_judged_by_what_the_other_rigs_could_know():
    predicted, measured = _tables()
    e = pl.evaluate(predicted, measured, RIGS, TRACKERS, level=0.8)
    planted = e["rigs"]["planted"]
    # the null, each tracker's mean over the other four rigs, picks `a`, which is 0.33 under the best there
    assert planted["regret"]["null"] == pytest.approx(0.93 - 0.60)
    assert planted["regret"]["method"] == 0.0  # the method, from the planted rig's own photographs, picks `b`
    assert planted["f1"]["method"]["error"] == pytest.approx(0.01)
    null = np.mean(measured["f1"][:4], axis=0)
    assert planted["f1"]["null"]["error"] == pytest.approx(np.mean(np.abs(null - measured["f1"][4])))
    assert e["pooled"]["f1"]["method"]["error"] < e["pooled"]["f1"]["null"]["error"]
    assert e["pooled"]["false_report_rate"]["method"]["error"] == pytest.approx(0.3)
    assert e["pooled"]["false_report_rate"]["null"]["error"] == pytest.approx(0.0)
    for rig in RIGS:  # every rig held out once, every tracker's interval scored
        assert e["rigs"][rig]["f1"]["method"]["n_intervals"] == 4
    assert e["pooled"]["f1"]["method"]["coverage"] == 1.0  # errors of 0.01, intervals of the other rigs' 0.01


def test_a_held_out_rig_never_calibrates_its_own_interval():
    """The planted rig's method is 0.3 off for one tracker: its interval, calibrated on the other rigs' errors of
    0.01, does not hold that figure; with the planted rig in the calibration (another rig held out) the half-width
    is still the other rigs' quantile, the one large error a single residual among many."""
    predicted, measured = _tables(planted_error=0.3)
    e = pl.evaluate(predicted, measured, RIGS, TRACKERS, level=0.8)
    planted = e["rigs"]["planted"]["f1"]["method"]
    assert planted["half_width"] == pytest.approx(0.01) and planted["covered"] == 3
    assert e["rigs"]["r1"]["f1"]["method"]["half_width"] == pytest.approx(0.01)


def test_the_calibration_states_the_null_where_the_method_is_further_off():
    predicted, measured = _tables()
    e = pl.evaluate(predicted, measured, RIGS, TRACKERS, level=0.8)
    c = pl.calibration(predicted, measured, RIGS, TRACKERS, e)
    assert c["f1"]["source"] == "method" and c["false_report_rate"]["source"] == "null"
    assert c["pick"]["source"] == "method" and c["f1"]["null"]["a"] == pytest.approx(np.mean(measured["f1"][:, 0]))
    s = pl.stated({f: predicted[f][4] for f in pl.FIGURES}, TRACKERS, c, n_draws=300)
    assert s["pick"] == "b" and s["false_report_rate"]["source"] == [pl.SOURCES["null"]] * 4
    assert s["false_report_rate"]["value"] == pytest.approx([0.05] * 4)
    assert s["f1"]["source"] == [pl.SOURCES["method"]] * 4
    # a tracker the calibration does not list has no null: its figures are the method's, uncalibrated
    s = pl.stated({f: np.r_[predicted[f][4], 0.5] for f in pl.FIGURES}, [*TRACKERS, "new"], c, n_draws=300)
    assert s["false_report_rate"]["source"][-1] == pl.SOURCES[None] and np.isnan(s["f1"]["lo"][-1])


def test_a_rig_without_a_prediction_is_stated_the_null_and_counted():
    predicted, measured = _tables()
    for f in predicted:
        predicted[f] = predicted[f].copy()
        predicted[f][2] = np.nan
    e = pl.evaluate(predicted, measured, RIGS, TRACKERS, level=0.8)
    assert e["rigs"]["r3"]["n_null"] == 4
    assert e["rigs"]["r3"]["f1"]["method"]["error"] == e["rigs"]["r3"]["f1"]["null"]["error"]


@pytest.mark.parametrize("adjust", ["blend", "bias"])
def test_the_declared_adjustments_are_fitted_on_the_training_rigs_only(adjust):
    """Toward the null and less its bias: with the method's false reports 0.3 too high on every rig, either brings
    them to the measured figure on the held-out rig from the other rigs alone."""
    predicted, measured = _tables()
    e = pl.evaluate(predicted, measured, RIGS, TRACKERS, level=0.8, adjust=adjust)
    assert e["adjust"] == adjust and e["pooled"]["false_report_rate"]["method"]["error"] < 0.01
    with pytest.raises(ValueError, match="`adjust` must be one of none, blend, bias"):
        pl.evaluate(predicted, measured, RIGS, TRACKERS, adjust="oracle")


def test_rig_table_pools_each_rig_s_photographs_rows():
    df = pd.DataFrame({"name": ["p1", "p2", "p3"], "tracker": ["a", "a", "a"], "n_hit": [8, 2, 5], "n_wrong": 0,
                       "n_missed": [2, 8, 5], "n_false": [0, 0, 1], "n_quiet": [0, 0, 9], "n_false_cut": [0, 0, 1],
                       "n_quiet_cut": [0, 0, 9]})
    t = pl.rig_table(df, "name", {"p1": "x", "p2": "x", "p3": "y"}, ["x", "y"], ["a", "b"])
    assert t["hit_rate"][0].tolist()[0] == pytest.approx(0.5) and np.isnan(t["hit_rate"][0, 1])
    assert t["false_report_rate"][1, 0] == pytest.approx(2 / 20)  # the false-report frames' rows counted


def test_fewer_than_three_rigs_cannot_calibrate():
    predicted, measured = _tables()
    with pytest.raises(ValueError, match="at least three rigs"):
        pl.evaluate({f: v[:2] for f, v in predicted.items()}, {f: v[:2] for f, v in measured.items()}, RIGS[:2],
                    TRACKERS)
