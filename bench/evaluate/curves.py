"""Curves and costs of a sweep: pure functions (tables in, records out).

A curve against key ``K`` holds every other swept key at its reference value:
the paper's operating point (400 lux, 3 mW) where the grid has it, else the
scene default, else the first value of the list (for ``material``: the
experiment's own material if swept, else the first). At each value the points
are the repeats; the curve is their mean and the band a 95 % t interval over
the repeats (none with a single repeat).
"""

from __future__ import annotations


from bench.evaluate.stats import t_interval

__all__ = ["reference_point", "curves", "per_unit_costs", "CURVE_METRICS", "PAPER_POINT"]

CURVE_METRICS = ("hit_rate", "depth_rmse_mm", "within_5mm")
PAPER_POINT = {"ambient_lux": 400.0, "laser_power_mw": 3.0}  # the paper's operating point
def _paper_or_default(key: str):
    from scenes import DEFAULTS

    return PAPER_POINT.get(key, DEFAULTS.get(key))


def reference_point(sweep_dict: dict, material: str | None = None) -> dict:
    """The reference value of every swept key (see the module docstring).

    Examples
    --------
    >>> reference_point({"ambient_lux": [0.0, 400.0, 1000.0], "laser_power_mw": [1.0, 10.0], "repeats": 2})
    {'ambient_lux': 400.0, 'laser_power_mw': 1.0}
    """
    ref = {}
    for key, values in sweep_dict.items():
        if key == "repeats":
            continue
        want = material if key == "material" else _paper_or_default(key)
        ref[key] = want if want in values else values[0]
    return ref


def curves(table, sweep, metrics=CURVE_METRICS) -> list[dict]:
    """Curve points: one record per experiment x swept key x value x tracker x metric.

    Parameters
    ----------
    table : pandas.DataFrame
        A sweep table (``sweep.parquet``).
    sweep : bench.run.sweep.Sweep or dict
        The sweep (anything with ``to_dict()``) or its dict.
    metrics : sequence of str

    Returns
    -------
    list of dict: ``experiment, key, value, tracker, metric, mean, low, high, n``
    (``n`` repeats with a value; ``low``/``high`` NaN when ``n < 2``).
    """
    sd = sweep if isinstance(sweep, dict) else sweep.to_dict()
    keys = [k for k in sd if k != "repeats"]
    out = []
    if table.empty:
        return out
    for exp, g in table.groupby("experiment", sort=False):
        ref = reference_point(sd, material=g["material"].iloc[0] if "material" in sd else None)
        for key in keys:
            sel = g
            for other in keys:
                if other != key:
                    sel = sel[sel[other] == ref[other]]
            for value in sd[key]:
                at = sel[sel[key] == value]
                for tracker, h in at.groupby("tracker", sort=False):
                    for m in metrics:
                        mean, lo, hi = t_interval(h[m].to_numpy(float))
                        out.append({"experiment": exp, "key": key, "value": value, "tracker": tracker, "metric": m,
                                    "mean": mean, "low": lo, "high": hi, "n": int(h[m].notna().sum())})
    return out


def per_unit_costs(units: list[dict]) -> list[dict]:
    """Measured costs per image size: render s per frame, evaluation s per frame x point x repeat
    (and the units' total ``setup_s``: trackers made and compiled, first-call imports; and
    ``render_s_per_later_frame``: render s per frame after each batch's first, i.e. without
    loading the scene and JIT compilation).

    Examples
    --------
    >>> per_unit_costs([{"width": 64, "height": 60, "frames": 2, "render_s": 1.0, "evaluations": 8,
    ...                  "eval_s": 0.4}])[0]["eval_s_per_evaluation"]
    0.05
    """
    by: dict[tuple, list] = {}
    for u in units:
        by.setdefault((u["width"], u["height"]), []).append(u)
    out = []
    for (w, h), us in sorted(by.items()):
        frames = sum(u["frames"] for u in us)
        ev = sum(u["evaluations"] for u in us)
        out.append({"width": w, "height": h, "units": len(us), "frames": frames, "evaluations": ev,
                    "render_s": sum(u["render_s"] for u in us), "eval_s": sum(u["eval_s"] for u in us),
                    "setup_s": sum(u.get("setup_s", 0.0) for u in us),
                    "render_s_per_later_frame": _later(us),
                    "render_s_per_frame": sum(u["render_s"] for u in us) / frames if frames else float("nan"),
                    "eval_s_per_evaluation": sum(u["eval_s"] for u in us) / ev if ev else float("nan")})
    return out


def _later(us: list[dict]) -> float:
    """Render s per frame after each batch's first (scene loading and JIT excluded)."""
    n = sum(u["frames"] - 1 for u in us)
    t = sum(u["render_s"] - u.get("first_render_s", float("nan")) for u in us)
    return t / n if n > 0 else float("nan")
