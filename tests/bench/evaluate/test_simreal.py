"""Per-image metrics and the sim-to-real comparison (bench.evaluate.simreal), and their HTML section."""

import numpy as np
import pytest

from bench.evaluate import simreal
from bench.report.simreal import sim_to_real_html


# ---------------------------------------------------------------------------------------------------- metrics


def test_image_metrics_against_hand_computed_values():
    cols = [10.0, 14.0, np.nan, 3.0, 20.5, 7.0]
    ref = [11.0, 10.0, 5.0, np.nan, 20.0, 10.0]
    m = simreal.image_metrics(cols, ref, tol_px=3.0)
    # reference rows 0, 1, 2, 4, 5: errors 1, 4, miss, 0.5, 3 (3 is a hit: |error| <= tol)
    assert m["n_ref"] == 5
    assert m["hit_rate"] == pytest.approx(3 / 5)
    assert m["mae_px"] == pytest.approx((1 + 0.5 + 3) / 3)
    assert m["coverage"] == pytest.approx(4 / 5)
    assert m["false_detections"] == pytest.approx(1.0)
    m = simreal.image_metrics(cols, ref, tol_px=0.5)
    assert m["hit_rate"] == pytest.approx(1 / 5) and m["mae_px"] == pytest.approx(0.5)
    empty = simreal.image_metrics([np.nan, np.nan], [np.nan, np.nan])
    assert np.isnan(empty["hit_rate"]) and np.isnan(empty["mae_px"]) and empty["false_detections"] == 0.0
    with pytest.raises(ValueError, match="`tol_px` must be a finite number >= 0"):
        simreal.image_metrics(cols, ref, tol_px=-1)


# ---------------------------------------------------------------------------------------------------- sim-to-real


def test_sim_to_real_rank_correlation_by_hand():
    syn = {"a": 0.9, "b": 0.8, "c": 0.7, "d": 0.6, "only_synthetic": 0.5}
    rea = {"a": 0.5, "b": 0.6, "c": 0.4, "d": 0.3, "only_real": 0.1}
    r = simreal.sim_to_real(syn, rea)
    # ranks (1 = best): synthetic a1 b2 c3 d4, real b1 a2 c3 d4; rho = 1 - 6 * 2 / (4 * 15) = 0.8
    assert r["n"] == 4 and r["spearman_rho"] == pytest.approx(0.8)
    assert [t["tracker"] for t in r["table"]] == ["b", "a", "c", "d"]
    assert r["table"][0]["delta"] == pytest.approx(-0.2) and r["table"][0]["rank_real"] == 1.0
    text = simreal.sim_to_real_sentences(r)
    assert text[0] == "Synthetic and real rankings of 4 trackers agree (Spearman's rho = 0.80)."
    # every real rate lies more than 0.10 below its synthetic one (deltas -0.4, -0.2, -0.3, -0.3)
    assert text[1] == ("The renders over-predict b (synthetic 0.80, real 0.60), a (synthetic 0.90, real 0.50), "
                       "c (synthetic 0.70, real 0.40), d (synthetic 0.60, real 0.30).")
    assert len(text) == 2
    html = sim_to_real_html(r)
    assert html.count("<tr>") == 5 and "Spearman" in html


def test_sim_to_real_under_prediction_and_too_few_trackers():
    r = simreal.sim_to_real({"a": 0.2, "b": 0.3}, {"a": 0.6, "b": 0.35})
    assert r["n"] == 2 and np.isnan(r["spearman_rho"])
    text = simreal.sim_to_real_sentences(r)
    assert text[0].startswith("Too few trackers") and text[1] == "The renders under-predict a (synthetic 0.20, real 0.60)."
    with pytest.raises(ValueError, match=r"`real_hit_rates\['a'\]` must be a hit rate in \[0, 1\], got 1.5"):
        simreal.sim_to_real({"a": 0.2}, {"a": 1.5})
