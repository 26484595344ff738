"""The report's pure pieces: verdict sentences, the at-a-glance table, the sweep families."""

import re

import pytest

from bench.report.run import glance_table, verdict_sentence
from bench.report.runfigures import _sweeps


def _fig(within, lo, hi, med, gross, n=100):
    return {"n": n, "within": within, "within_low": lo, "within_high": hi, "median_abs_mm": med, "n_gross": gross}


def _verdict(w, m):
    return {"dp": "dp4", "baseline": "threshold", "within": w, "rmse": m, "dp_figures": _fig(0.9, 0.8, 0.95, 0.5, 0),
            "baseline_figures": _fig(0.5, 0.4, 0.6, 3.0, 7), "ratio": {"value": 0.4, "low": 0.1, "high": 0.6}}


def test_verdict_sentences_say_what_the_intervals_say():
    assert verdict_sentence(_verdict("dp4", "dp4")).startswith("dp4 is more precise than threshold by both")
    assert verdict_sentence(_verdict("tie", "tie")).startswith("neither dp4 nor threshold is more precise")
    assert verdict_sentence(_verdict("tie", "threshold")).startswith("threshold is more precise by the RMSE ratio, but")
    assert verdict_sentence(_verdict("dp4", "tie")).startswith("dp4 is more precise by the ±5 mm fraction, but")
    s = verdict_sentence(_verdict("dp4", "threshold"))
    assert s.startswith("the statistics disagree: dp4 wins by the ±5 mm fraction, threshold by the RMSE ratio")
    assert "90 % [80 %, 95 %]" in s and "gross errors (&gt; 50 mm) 0 against 7" in s


def test_glance_table_marks_the_best_of_each_condition_and_ranks_by_the_mean():
    robust = []
    for group, figs in (("condition:a", {"t1": (0.5, 1.0), "t2": (0.9, 0.4), "t3": (0.9, 0.2)}),
                        ("b-x", {"t1": (0.99, 0.1), "t2": (0.2, 9.0), "t3": (0.8, 0.3)})):
        for name, (w, med) in figs.items():
            robust.append({"group": group, "tracker": name, **_fig(w, w - 0.05, w + 0.05, med, 0)})
    summary = {"robust": robust, "conditions": [{"condition": "a", "experiments": ["a-x", "a-y"]},
                                                {"condition": "b-x", "experiments": ["b-x"]}]}
    page = glance_table(summary)
    rows = re.findall(r"<tr><td>(\d)</td><th[^>]*>(\w+)</th>(.*?)</tr>", page)
    assert [(r[0], r[1]) for r in rows] == [("1", "t3"), ("2", "t1"), ("3", "t2")]  # means 0.85, 0.745, 0.55
    stars = {name: cells.count("★") for _, name, cells in rows}
    assert stars == {"t3": 1, "t1": 1, "t2": 0}  # a: t3 (ties t2 on the fraction, lower median); b: t1


def test_sweep_families_are_experiments_differing_in_one_numeric_override():
    exps = [{"scene": "cone", "material": "patchy", "n_angles": 2, "ambient_lux": v} for v in (0.0, 400.0, 1000.0)]
    exps.append({"scene": "cone", "material": "matte", "n_angles": 2})
    fams = _sweeps({"render": {"width": 64, "height": 60}, "experiments": exps, "trackers": ["threshold"],
                    "baselines": [], "dp": []})
    assert fams == [("cone/patchy", "ambient_lux", ["cone-patchy_ambient_lux=0.0", "cone-patchy_ambient_lux=400.0",
                                                    "cone-patchy_ambient_lux=1000.0"])]


def test_a_report_reads_only_what_the_run_saved(tiny_run, tmp_path, monkeypatch):
    """A run's report is rebuilt where the run's real set is gone and the machine has less memory."""
    import json
    import shutil

    from bench import config as config_mod
    from bench.config import schema
    from bench.report.run import build_report

    out, _ = tiny_run
    copy = tmp_path / "moved"
    shutil.copytree(out, copy)
    summary = json.loads((copy / "summary.json").read_text())
    summary["config"]["real_set"] = str(tmp_path / "a-real-set-that-was-moved")
    (copy / "summary.json").write_text(json.dumps(summary))
    monkeypatch.setattr(schema, "memory_limit_bytes", lambda: 1)  # where `parse` looks it up
    with pytest.raises(config_mod.ConfigError):  # the live checks would refuse this configuration here
        config_mod.parse(summary["config"])
    assert build_report(copy, quiet=True).is_file()


def test_the_report_draws_the_saved_cost_field_and_rigs_without_recomputing(tiny_run, tmp_path, monkeypatch):
    """Fig. 7b's cost field and each experiment's rig come from the run's files (issue 36)."""
    import json
    import shutil

    import numpy as np

    import scenes
    import trackers.dp
    from bench.report.run import build_report
    from bench.store.figdata import read_figdata

    out, _ = tiny_run
    fd, why = read_figdata(out / "figdata.npz")
    assert why is None and np.array_equal(fd.cost_field, trackers.dp.accumulated_cost(fd.image, connectivity=4))
    summary = json.loads((out / "summary.json").read_text())
    assert all(isinstance(s["rig"], dict) for s in summary["scans"])
    copy = tmp_path / "run"
    shutil.copytree(out, copy)

    def refuse(*a, **k):
        raise AssertionError("the report recomputed what the run saved")

    monkeypatch.setattr(trackers.dp, "accumulated_cost", refuse)
    monkeypatch.setattr(scenes, "make", refuse)
    monkeypatch.setattr("bench.report.runfigures.figure_workers", lambda n, workers=None: 0)  # drawn here, where the patch is
    assert build_report(copy, quiet=True).is_file()


def test_a_report_loads_neither_the_renderer_nor_a_tracker(tiny_run, tmp_path):
    """The report reads what the run saved: building it (in a fresh process) imports no renderer
    (Mitsuba, Dr.Jit) and no tracker (only :mod:`trackers`' registry and process helpers), so it can
    neither render nor track again."""
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    copy = tmp_path / "run"
    shutil.copytree(tiny_run[0], copy)
    code = ("import sys; from bench.report.run import build_report; build_report(sys.argv[1], quiet=True); "
            "print(' '.join(m for m in sys.modules if m.split('.')[0] in ('mitsuba', 'drjit', 'trackers')))")
    out = subprocess.run([sys.executable, "-c", code, str(copy)], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).resolve().parents[3])
    loaded = out.stdout.split()
    assert "trackers" in loaded  # the check sees the modules
    assert [m for m in loaded if m.split(".")[0] in ("mitsuba", "drjit")] == []
    assert [m for m in loaded if m.startswith("trackers.") and not m.split(".")[1].startswith("_")
            and m != "trackers.processes"] == []


EVIL = "<script>alert('x')</script> \"q\""


def _claim(baseline, reading, paper):
    from bench.evaluate.readings import READINGS

    figs = {"dp_within": 0.98, "dp_within_low": 0.96, "dp_within_high": 0.99, "baseline_within": 0.65,
            "baseline_within_low": 0.59, "baseline_within_high": 0.7, "n": 300, "ratio_value": 0.1,
            "ratio_low": -0.2, "ratio_high": 0.3, "ratio_n": 195, "n_samples": 300, "n_missing_dp": 0,
            "n_missing_baseline": 105 if reading == "gaps" else 0}
    return {"baseline": baseline, "reading": reading, "description": READINGS[reading], "paper_reading": paper,
            "dp": "dp4", "group": f"condition:{EVIL}", "experiments": ["cone-paper", "hand-paper"],
            "claims": {"most_within": "reproduced", "more_precise": "reproduced", "improvement": "reproduced"},
            "figures": figs, "outside": 105, "outside_undetectable": 105, "sentence": f"plain {EVIL}"}


def test_the_headline_is_one_sentence_per_reading_and_escapes_what_it_shows():
    from bench.report.run import claims_html

    summary = {"paper_claims": [_claim("threshold", "filled", False), _claim("threshold_gaps", "gaps", False),
                                _claim("argmax", "argmax", True)],
               "conditions": [{"condition": EVIL, "experiments": ["cone-paper", "hand-paper"]}],
               "within_mm": 5.0, "paper_improvement": 0.30}
    page = claims_html(summary)
    assert "<script>" not in page and "&lt;script&gt;alert(&#x27;x&#x27;)&lt;/script&gt; &quot;q&quot;" in page
    first = page.split("<details")[0]  # the sentences before the folded explanation
    assert first.count("<li>") == 3 and "over the 195 of 300 pairs where both have a depth" in first
    assert first.count("the reading the paper's text supports") == 1
    assert "<b><code>argmax</code></b> (the brightest pixel of every row), <i>the reading" in first
    assert claims_html({"paper_claims": []}) == ""


def test_verdicts_are_folded_per_condition_and_escaped():
    from bench.report.run import _verdicts_folded

    v = _verdict("dp4", "tie") | {"group": f"condition:{EVIL}"}
    w = dict(v, baseline="argmax")
    summary = {"verdicts": [v, w], "config": {"baselines": ["threshold", "argmax"]},
               "robust": [{"group": f"condition:{EVIL}", "tracker": "dp4"}],
               "conditions": [{"condition": EVIL, "experiments": ["a", "b"]}]}
    page = _verdicts_folded(summary)
    assert "<script>" not in page and "&lt;script&gt;" in page
    assert page.startswith("<details><summary>") and "against the other baselines" in page
    assert page.count("<details>") == 2  # the condition, and the other baselines inside it


def test_glance_table_escapes_condition_titles_and_says_each_settings_restoration():
    robust = [{"group": EVIL, "tracker": t, **_fig(0.9, 0.8, 0.95, 0.3, 0)} for t in ("threshold", "threshold_gaps")]
    summary = {"robust": robust, "conditions": [{"condition": EVIL, "experiments": [EVIL]}], "restore": "rows",
               "restore_by_tracker": {"threshold": "rows", "threshold_gaps": "none"},
               "config": {"restore": "rows", "trackers": [
                   "threshold", {"label": "threshold_gaps", "name": "threshold", "params": {}, "restore": "none"}]}}
    page = glance_table(summary)
    assert "<script>" not in page and "&lt;script&gt;" in page
    assert "<code>none</code> for <code>threshold_gaps</code>" in page
    assert 'title="threshold, missed rows have no depth; restoration none"' in page


def test_figures_drawn_in_worker_processes_are_the_same_files(tiny_run, tmp_path):
    """The 2-D figures drawn in worker processes are byte for byte those drawn in this process, in the
    same sections and order."""
    import shutil

    from bench.report.runfigures import make_figures

    out, _ = tiny_run
    here, there = tmp_path / "here", tmp_path / "there"
    shutil.copytree(out, here)
    shutil.copytree(out, there)
    serial = make_figures(here, quiet=True, workers=0)
    parallel = make_figures(there, quiet=True, workers=2)
    assert {k: [p.name for p in v] for k, v in serial.items()} == {k: [p.name for p in v] for k, v in parallel.items()}
    flat = [p for k, v in serial.items() if k != "shapes" for p in v]
    assert len(flat) >= 3
    for p in flat:
        assert p.read_bytes() == (there / "figures" / p.name).read_bytes(), p.name


def test_figure_workers_validates_its_argument():
    from bench.report.runfigures import figure_workers

    assert figure_workers(0, 2) == 0
    for bad in (-1, 1.5, True, "2"):
        with pytest.raises(ValueError, match="`workers` must be an integer >= 0 or None"):
            figure_workers(10, bad)


def test_figures_are_drawn_here_when_no_worker_process_starts(tiny_run, tmp_path, monkeypatch, capsys):
    import concurrent.futures
    import shutil

    from bench.report.runfigures import make_figures

    class NoProcesses:
        def __init__(self, *args, **kwargs):
            raise OSError("no semaphores here")

    out, _ = tiny_run
    here = tmp_path / "here"
    shutil.copytree(out, here)
    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", NoProcesses)
    figs = make_figures(here, quiet=True, workers=2)
    assert figs["gallery"] and all(p.is_file() for p in figs["gallery"])
    assert "figures drawn in this process: the worker processes failed (OSError: no semaphores here)" in \
        capsys.readouterr().err


def test_the_headline_says_not_determined_where_the_interval_is_as_wide_as_the_claim():
    from bench.report.run import claims_html

    figures = {"dp_within": 0.99, "dp_within_low": 0.97, "dp_within_high": 0.99, "baseline_within": 0.98,
               "baseline_within_low": 0.95, "baseline_within_high": 0.99, "n": 300, "ratio_value": 0.86,
               "ratio_low": 0.03, "ratio_high": 0.94, "ratio_n": 300, "n_samples": 300, "n_missing_dp": 0,
               "n_missing_baseline": 0}
    entry = {"baseline": "threshold", "reading": "filled", "description": "threshold, missed rows filled",
             "paper_reading": False, "dp": "dp4_oneframe", "group": "condition:p", "experiments": ["a"],
             "claims": {"most_within": "reproduced", "more_precise": "reproduced", "improvement": "reproduced"},
             "figures": figures, "sentence": ""}
    page = claims_html({"paper_claims": [entry], "conditions": [{"condition": "p", "experiments": ["a"]}]})
    assert "? not determined" in page and "as wide as the claim" in page and "✔ reproduced</b> (RMSE" not in page
    narrow = dict(entry, figures={**figures, "ratio_low": 0.22, "ratio_high": 0.41})
    page = claims_html({"paper_claims": [narrow], "conditions": [{"condition": "p", "experiments": ["a"]}]})
    assert "improvement <b>✔ reproduced</b>" in page and "not determined" not in page


def test_the_page_links_its_figures_folds_the_rest_and_scrolls_wide_tables(tiny_run):
    from html.parser import HTMLParser

    out, _ = tiny_run
    page = (out / "report.html").read_text()

    class Walk(HTMLParser):
        def __init__(self):
            super().__init__()
            self.stack, self.loose, self.tables, self.folded_tables = [], [], 0, 0

        def handle_starttag(self, tag, attrs):
            a = dict(attrs)
            if tag == "table":
                self.tables += 1
                boxed = any(t == "div" and "scroll" in (c or "").split() for t, c in self.stack)
                if not boxed and "glance" not in (a.get("class") or ""):
                    self.loose.append(a)
                self.folded_tables += any(t == "details" for t, _ in self.stack)
            if tag not in ("img", "br", "col", "meta", "input", "hr"):
                self.stack.append((tag, a.get("class")))

        def handle_endtag(self, tag):
            while self.stack:
                if self.stack.pop()[0] == tag:
                    break

    w = Walk()
    w.feed(page)
    assert w.tables > 5 and w.loose == []  # every table but the glance tables (fixed width) scrolls in a box
    assert w.folded_tables >= 4  # the ratio, hit-rate and metrics tables are folded
    assert "data:image" not in page and "<h2>Failure gallery</h2><details><summary>the " in page
    assert "Drawn, one panel each: <code>dp4</code>, <code>dp8</code>, <code>threshold</code>" in page
    assert "left out (see the tables): <code>centroid</code>" in page
