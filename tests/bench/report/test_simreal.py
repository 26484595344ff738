"""The sim-to-real section of a run's report, rendered from a small table as the run saves it in summary.json."""

import json
import re

from bench.evaluate import simreal
from bench.report.simreal import predicted_html, sim_to_real_by_class_html, sim_to_real_html

EVIL = "<b>x</b>'"


def _saved(doc):
    """``doc`` as the report reads it back: through JSON, as summary.json holds it (NaN included)."""
    return json.loads(json.dumps(doc))


def _result():
    """A :func:`bench.evaluate.simreal.sim_to_real` result as a run writes it (bench.run.experiment)."""
    r = simreal.sim_to_real({"a": 0.9, "b": 0.5, EVIL: 0.7}, {"a": 0.6, "b": 0.45, EVIL: 0.7})
    r["dataset"] = "shipped"
    r["sentences"] = simreal.sim_to_real_sentences(r)
    r["detection"] = {"f1": simreal.sim_to_real({"a": 0.8, "b": 0.4}, {"a": 0.7, "b": 0.5}),
                      "false_report_rate": simreal.sim_to_real({"a": 0.1, EVIL: 0.3}, {"a": 0.2, EVIL: 0.0})}
    return _saved(r)


def _cells(fragment: str) -> list[list[str]]:
    """Each table row's cells (header and data), in order."""
    return [re.findall(r"<t[hd]>(.*?)</t[hd]>", row) for row in re.findall(r"<tr>(.*?)</tr>", fragment)]


def test_the_section_shows_the_saved_table_and_sentences():
    page = sim_to_real_html(_result())
    assert page.startswith("<section class='sim-to-real'><h2>Renders vs photographs</h2>") and page.endswith("</section>")
    rows = _cells(page)
    assert rows[0] == ["tracker", "synthetic hit rate", "real hit rate", "real - synthetic", "rank (synthetic)",
                       "rank (real)"]
    by = {r[0]: r[1:] for r in rows[1:4]}
    assert by["a"] == ["0.900", "0.600", "-0.300", "1", "2"]
    assert by["b"] == ["0.500", "0.450", "-0.050", "3", "3"]
    assert "<p>hit rate: the renders over-predict a (synthetic 0.90, real 0.60).</p>" in page


def test_the_headline_speaks_of_both_halves():
    """Issue 66: the sentences compare F1 over rows and the false-report rate too, not the hit rates alone."""
    page = sim_to_real_html(_result())
    assert "<p>F1 over rows: too few trackers with distinct figures (2) for a rank correlation.</p>" in page
    assert ("<p>false-report rate: the renders over-predict &lt;b&gt;x&lt;/b&gt;&#x27; (synthetic 0.30, real 0.00)."
            "</p>") in page
    assert "<p>false-report rate: the renders under-predict a (synthetic 0.10, real 0.20).</p>" not in page  # 0.10


def test_detection_beside_the_hit_rates_marks_a_tracker_that_one_half_lacks():
    rows = _cells(sim_to_real_html(_result()).split("Both halves of detection")[1])
    assert rows[0] == ["tracker", "F1 over rows<br>synthetic / real", "false-report rate<br>synthetic / real"]
    by = {r[0]: r[1:] for r in rows[1:]}
    assert by["a"] == ["0.800 / 0.700", "0.100 / 0.200"]
    assert by["b"] == ["0.400 / 0.500", "–"]  # scored for F1 only
    assert by["&lt;b&gt;x&lt;/b&gt;&#x27;"] == ["–", "0.300 / 0.000"]


def test_every_name_is_escaped():
    page = sim_to_real_html(_result())
    assert "<b>x</b>" not in page and page.count("&lt;b&gt;x&lt;/b&gt;&#x27;") == 3  # hit rates, detection, sentence
    r = _result()
    r["detection"] = {}
    assert "Both halves" not in sim_to_real_html(r)  # a run saved before detection was compared


def test_the_by_class_section_from_a_saved_comparison():
    syn = {"x": {"a": 0.9, "b": 0.7, "c": 0.5}, EVIL: {"a": 0.2, "b": 0.6}}
    per_image = {"p1": {"a": 0.8, "b": 0.6, "c": 0.1}, "p2": {"a": 0.6, "b": 0.2, "c": 0.3}, "q": {"a": 0.5, "b": 0.3}}
    r = _saved(simreal.sim_to_real_by_class(syn, per_image, {"p1": "x", "p2": "x", "q": EVIL}))
    page = sim_to_real_by_class_html(r)
    assert "<b>x</b>" not in page and "matched classes: &lt;b&gt;x&lt;/b&gt;&#x27;, x." in page
    classes, trackers = (_cells(t) for t in page.split("</table>")[:2])
    assert classes[0] == ["class", "rendered", "photographs", "names", "trackers", "Spearman's rho"]
    assert classes[1] == ["&lt;b&gt;x&lt;/b&gt;&#x27;", "yes", "1", "q", "2", "–"]  # two trackers: no rho
    assert classes[2] == ["x", "yes", "2", "p1, p2", "3", "1.00"]
    assert trackers[0] == ["tracker", "&lt;b&gt;x&lt;/b&gt;&#x27;<br>synthetic / real", "x<br>synthetic / real",
                           "matched classes, mean<br>synthetic / real", "mean |synthetic - real|"]
    assert trackers[1:] == [["a", "0.200 / 0.500", "0.900 / 0.700", "0.550 / 0.600", "0.250"],
                            ["b", "0.600 / 0.300", "0.700 / 0.400", "0.650 / 0.350", "0.300"]]  # c: not in every class
    assert "too few trackers with distinct rates for a rank correlation" in page


def test_predicted_beside_measured_is_escaped_and_names_what_was_left_out():
    import pandas as pd

    from bench.evaluate.prediction import compare_with_real, comparison_doc

    pred = pd.DataFrame({"tracker": ["a", EVIL], "hit_rate": [0.9, 0.5], "f1": [0.8, 0.6],
                         "false_report_rate": [0.0, 0.1]})
    rows = [{"experiment": "p", "tracker": t, "n_hit": h, "n_wrong": 0, "n_missed": 10 - h, "n_false": 0,
             "n_quiet": 0} for t, h in (("a", 8), (EVIL, 4))]
    doc = _saved({"photographs": ["p"], "frames": "transplant", "out_of_range": {"wide": ["visible"]},
                  **comparison_doc(compare_with_real(pred, pd.DataFrame(rows), ["p"])),
                  "rigs": {"someone/rig": comparison_doc({"photographs": ["p"],
                                                          **compare_with_real(pred, pd.DataFrame(rows), ["p"])})}})
    html = predicted_html(doc)
    assert EVIL not in html and "&lt;b&gt;x&lt;/b&gt;" in html
    cells = _cells(html)
    assert cells[1][:3] == ["a", "0.900", "0.800"] and "someone/rig" in html
    # the reason in its one wording (bench.evaluate.stripe.why_left_out), not a hand-written one
    from bench.evaluate.stripe import why_left_out

    assert f"Left out: wide ({why_left_out(['visible'])})" in html and "too few rows seen" not in html
    shrunk = predicted_html({**doc, "shrunk": {"big": 2}, "why": {"big": why_left_out(["width_px"], width_px=18.4)}})
    assert "Predicted shrunk (a coarse answer): big by 2 (its stripe is 18.4 px wide, wider than the reference " \
           "window&#x27;s 13 px)" in shrunk
    assert "How repeatable" not in html  # no reliability: fewer than 4 photographs


def test_predicted_beside_measured_says_how_repeatable_the_measured_ranks_are():
    import pandas as pd

    from bench.evaluate.prediction import compare_with_real, comparison_doc, rank_interval, rank_reliability

    names = [f"p{i}" for i in range(6)]
    pred = pd.DataFrame({"tracker": ["a", "b", "c"], "hit_rate": [0.9, 0.5, 0.7], "f1": [0.8, 0.6, 0.7],
                         "false_report_rate": [0.0, 0.1, 0.2]})
    rows = pd.DataFrame([{"experiment": n, "tracker": t, "n_hit": h, "n_wrong": 0, "n_missed": 10 - h, "n_false": 1,
                          "n_quiet": 9} for n in names for t, h in (("a", 9), ("b", 5), ("c", 7))])
    doc = _saved({"photographs": names, "frames": "transplant", **comparison_doc(compare_with_real(pred, rows, names)),
                  "rigs": {"someone/rig": {**comparison_doc({"photographs": names,
                                                             **compare_with_real(pred, rows, names)}),
                                           "measured_reliability": rank_reliability(rows, names, n_splits=10),
                                           "rank_interval": rank_interval(rows.assign(name=rows["experiment"]), rows,
                                                                          names, n_draws=10)},
                           "small/rig": comparison_doc({"photographs": names[:2],
                                                        **compare_with_real(pred, rows, names[:2])})},
                  "measured_reliability": rank_reliability(rows, names, n_splits=10)})
    html = predicted_html(doc)
    assert "How repeatable the measured ranks are" in html and "hit rate 1.00 (all photographs: 1.00)" in html
    cells = _cells(html)
    rig_rows = {c[0]: c for c in cells if c and c[0] in ("someone/rig", "small/rig")}
    assert rig_rows["someone/rig"][-1] == "1.00 / 1.00" and rig_rows["small/rig"][-1] == "–"
    assert rig_rows["someone/rig"][-2] == "1.00 to 1.00 / 1.00 to 1.00" and rig_rows["small/rig"][-2] == "–"
