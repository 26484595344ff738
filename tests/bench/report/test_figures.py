import numpy as np
import pandas as pd

from bench.report import figures


def test_fig10_clips_nothing_silently():
    y, clipped, missing = figures.clip_for_plot([3.0, -2e4, 1500.0, np.nan, -999.0], cap=1000.0)
    np.testing.assert_array_equal(clipped, [False, True, True, False, False])
    np.testing.assert_array_equal(missing, [False, False, False, True, False])
    assert y[1] == -1000.0 and y[2] == 1000.0 and y[4] == -999.0


def test_fig10_marks_and_counts_clipped_samples(tmp_path, monkeypatch):
    s = pd.DataFrame({"error_mm_dp": [0.1, 2e4, np.nan, -3.0], "error_mm_th": [0.2, -30.0, 1.0, -5e3]})
    labels = []
    import matplotlib.axes

    real_legend = matplotlib.axes.Axes.legend

    def spy(self, *a, **k):
        labels.extend(h.get_label() for h in self.get_legend_handles_labels()[0])
        return real_legend(self, *a, **k)

    monkeypatch.setattr(matplotlib.axes.Axes, "legend", spy)
    p = figures.fig_samples(s, "dp", "th", tmp_path / "f.png", title="t")
    assert p.is_file()
    assert "dp: 1 beyond ±1000 mm (at the edge)" in labels and "th: 1 beyond ±1000 mm (at the edge)" in labels
    assert "dp: 1 with no value" in labels


def test_tracker_colours_follow_the_label_not_the_position():
    assert figures.tracker_colour("dp4") == figures.TRACKER_COLOURS["dp4"]
    assert figures.tracker_colour("my_plugin") == figures.tracker_colour("my_plugin")
    registered = [figures.tracker_colour(n) for n in ("threshold", "centroid", "dp4", "dp8", "gauss3", "parabolic",
                                                       "blais_rioux", "steger", "com_bg", "dp8_subpixel")]
    assert len(set(registered)) == len(registered)


def test_bars_of_two_experiments_of_one_scene_and_material(tmp_path):
    m = pd.DataFrame({"experiment": ["cone-patchy_ambient_lux=0", "cone-patchy_ambient_lux=400"] * 2,
                      "scene": "cone", "material": "patchy", "tracker": ["a", "a", "b", "b"], "region": "object",
                      "hit_rate": [0.9, 0.5, 0.8, np.nan]})
    assert figures.fig_bars(m, tmp_path / "b.png").is_file()


def test_fig10_of_two_readings_side_by_side_marks_where_the_threshold_sees_nothing(tmp_path, monkeypatch):
    import matplotlib.axes

    s = pd.DataFrame({"error_mm_dp": [0.1, 0.2, -0.3, 0.4], "error_mm_argmax": [0.2, 80.0, -300.0, 1.0],
                      "error_mm_threshold": [0.2, 1.0, -2.0, 1.0]})
    labels, titles = [], []
    real_legend = matplotlib.axes.Axes.legend

    def spy(self, *a, **k):
        labels.append([h.get_label() for h in self.get_legend_handles_labels()[0]])
        titles.append(self.get_title())
        return real_legend(self, *a, **k)

    monkeypatch.setattr(matplotlib.axes.Axes, "legend", spy)
    stat = {"argmax": {"value": 0.9, "low": 0.8, "high": 0.95, "n": 4, "n_samples": 4}, "threshold": None}
    p = figures.fig_samples(s, "dp", ["argmax", "threshold"], tmp_path / "f.png", title="t", stat=stat,
                            undetectable=[False, True, True, False],
                            readings={"argmax": "the brightest pixel of every row"})
    assert p.is_file() and len(labels) == 2  # one panel per reading
    assert "argmax where the threshold detects no stripe: 2, 2 outside ±5 mm" in labels[0]
    assert "threshold where the threshold detects no stripe: 2, 0 outside ±5 mm" in labels[1]
    assert "without DP: argmax (the brightest pixel of every row)" in titles[0] and "= 90 %" in titles[0]


def test_fig10_names_the_papers_ratio_from_its_one_home(tmp_path, monkeypatch):
    import matplotlib.axes

    from bench.evaluate.outcomes import PAPER_IMPROVEMENT

    titles = []
    real_legend = matplotlib.axes.Axes.legend

    def spy(self, *a, **k):
        titles.append(self.get_title())
        return real_legend(self, *a, **k)

    monkeypatch.setattr(matplotlib.axes.Axes, "legend", spy)
    s = pd.DataFrame({"error_mm_dp": [0.1, 0.2], "error_mm_th": [0.2, 9.0]})
    stat = {"value": 0.9, "low": 0.8, "high": 0.95, "n": 2, "n_samples": 2}
    figures.fig_samples(s, "dp", "th", tmp_path / "a.png", stat=stat)
    figures.fig_samples(s, "dp", "th", tmp_path / "b.png", stat=stat, paper_improvement=0.25)
    assert titles[0].endswith(f"paper: {100 * PAPER_IMPROVEMENT:.0f} %") and titles[1].endswith("paper: 25 %")


def test_the_shapes_figure_draws_every_reading_and_every_submission():
    from bench.config import profile
    from bench.report.runfigures import shape_labels

    cfg = profile("paper").to_dict()
    shown, left = shape_labels({"config": cfg})
    assert {"threshold", "threshold_gaps", "argmax"} <= set(shown)  # every reading of the paper's baseline
    assert shown[0] == cfg["dp"][0] and "centroid" not in shown  # the headline's DP first; not a reading
    assert set(shown) | set(left) == {t if isinstance(t, str) else t["label"] for t in cfg["trackers"]}
    assert not set(shown) & set(left)
    shown, _ = shape_labels({"config": cfg, "submission": {"label": "mine"}})
    assert shown[-1] == "mine"
    alone = {**cfg, "trackers": [], "baselines": [], "dp": []}  # score --alone: the submission only
    assert shape_labels({"config": alone, "submission": {"label": "mine"}}) == (["mine"], [])
