"""``stripebench leaderboard``: the trackers of comparable runs ranked per condition, one HTML page and a CSV.

Runs are comparable when :func:`bench.run.gate.comparability` finds no
difference among :data:`bench.run.gate.COMPARED_KEYS` (render size and spp,
experiments, seed); otherwise the page is refused in one line. Each tracker
label enters once (from the first run that has it). Per condition, trackers
are ranked by the fraction of sample points within ±5 mm (``within``, missing
points counted as misses) with its Wilson 95 % interval; a tracker whose
interval overlaps the one ranked above it is marked tied and shares its rank
(the report's rule: intervals overlap => tie). Beside it: median |error|,
RMSE, gross errors, ms per frame (the mean over the condition's experiments
of ``timings.csv``) and the run and code revision the entry comes from.
"""

from __future__ import annotations

import csv
import html
import io
import math
from pathlib import Path

from bench.run import gate
from bench.store.files import atomic_write_text
from bench.store.runfolder import RunFolderError, load_metrics, load_summary

__all__ = ["LeaderboardError", "leaderboard_rows", "build_leaderboard", "COLUMNS"]

COLUMNS = ("condition", "rank", "tied", "tracker", "within", "within_low", "within_high", "median_abs_mm",
           "rmse_mm", "n_gross", "n", "ms_per_frame", "run", "kind", "git_revision")


class LeaderboardError(ValueError):
    """Runs that cannot share a leaderboard; one line."""


def _group_of(summary: dict, cond: dict, robust_groups: set) -> str | None:
    g = f"condition:{cond['condition']}"
    if g in robust_groups:
        return g
    if len(cond["experiments"]) == 1 and cond["experiments"][0] in robust_groups:
        return cond["experiments"][0]
    return None


def leaderboard_rows(runs) -> list[dict]:
    """One row per condition x tracker of the runs (:data:`COLUMNS`), ranked.

    Raises
    ------
    LeaderboardError
        A run is not a finished run or scored submission, or two runs are not comparable.
    """
    loaded = []
    for r in runs:
        try:
            s = load_summary(r)
        except RunFolderError as exc:
            raise LeaderboardError(str(exc)) from None
        if s["kind"] not in ("run", "score"):
            raise LeaderboardError(f"{str(r)!r} is a {s['kind']} run; a leaderboard ranks runs and scored "
                                   "submissions of synthetic frames")
        loaded.append((Path(r), s, load_metrics(r, timings=True)))
    first = loaded[0][1]["config"]
    for path, s, _ in loaded[1:]:
        diff = gate.comparability(first, s["config"])
        if diff:
            raise LeaderboardError(f"{str(path)!r} is not comparable with {str(loaded[0][0])!r}: they differ in "
                                   f"{'; '.join(diff)}")
    seen, per_cond = set(), {}
    for path, s, m in loaded:
        rob = {(x["group"], x["tracker"]): x for x in s.get("robust", [])}
        groups = {g for g, _ in rob}
        for cond in s.get("conditions", []):
            g = _group_of(s, cond, groups)
            if g is None:
                continue
            mm = m[(m["region"] == "all") & m["experiment"].isin(cond["experiments"])]
            for (gg, label), x in rob.items():
                if gg != g or (cond["condition"], label) in seen:
                    continue
                seen.add((cond["condition"], label))
                t = mm[mm["tracker"] == label]["ms_per_frame"].astype(float)
                ms = float(t.mean()) if t.notna().any() else float("nan")
                per_cond.setdefault(cond["condition"], []).append({
                    "condition": cond["condition"], "tracker": label, "within": x["within"],
                    "within_low": x["within_low"], "within_high": x["within_high"],
                    "median_abs_mm": x["median_abs_mm"], "rmse_mm": x["rmse_mm"], "n_gross": x["n_gross"],
                    "n": x["n"], "ms_per_frame": ms, "run": path.name, "kind": s["kind"],
                    "git_revision": s.get("git_revision", "")})
    out = []
    for cond, rows in per_cond.items():
        rows.sort(key=lambda r: (-(r["within"] if _ok(r["within"]) else -1.0), r["tracker"]))
        rank = 0
        for i, r in enumerate(rows):
            prev = rows[i - 1] if i else None
            tied = prev is not None and _ok(r["within_high"]) and _ok(prev["within_low"]) \
                and r["within_high"] >= prev["within_low"]
            rank = rank if tied else i + 1
            out.append({"rank": rank, "tied": bool(tied), **r})
    return [{k: r[k] for k in COLUMNS} for r in out]


def _ok(v) -> bool:
    return isinstance(v, (int, float)) and math.isfinite(v)


def _f(v, fmt: str) -> str:
    return format(v, fmt) if _ok(v) else "–"


def build_leaderboard(runs, out_dir) -> Path:
    """Write ``leaderboard.html`` and ``leaderboard.csv`` into ``out_dir``; returns the page.

    Raises
    ------
    LeaderboardError
        See :func:`leaderboard_rows`.
    """
    rows = leaderboard_rows(runs)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    atomic_write_text(out_dir / "leaderboard.csv", buf.getvalue())
    e = html.escape
    parts = ["<!doctype html><meta charset='utf-8'><title>stripebench leaderboard</title>",
             "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;margin-bottom:2em}"
             "td,th{padding:4px 10px;border-bottom:1px solid #ddd;text-align:right}td.l,th.l{text-align:left}"
             ".bar{display:inline-block;height:10px;background:#4a7;vertical-align:middle}"
             ".tie{color:#a60}</style>",
             "<h1>stripebench leaderboard</h1>",
             f"<p>{len(list(runs))} comparable run(s). Ranked per condition by the fraction of sample points within "
             "±5 mm (95 % Wilson interval; missing points count as misses). <span class='tie'>tie</span>: its "
             "interval overlaps the one ranked above, so it shares that rank. Times are ms per frame (a "
             "submission's own times.csv, else the harness's clock; machine dependent).</p>"]
    for cond in dict.fromkeys(r["condition"] for r in rows):
        parts.append(f"<h2>{e(cond)}</h2><table><tr><th>rank</th><th class='l'>tracker</th><th>±5 mm</th>"
                     "<th class='l'>95 % interval</th><th>median |e| mm</th><th>RMSE mm</th><th>gross</th>"
                     "<th>n</th><th>ms/frame</th><th class='l'>run</th><th class='l'>code</th></tr>")
        for r in (x for x in rows if x["condition"] == cond):
            lo, hi = r["within_low"], r["within_high"]
            bar = (f"<span class='bar' style='margin-left:{100 * lo:.0f}px;width:{max(1, 100 * (hi - lo)):.0f}px'>"
                   "</span>") if _ok(lo) and _ok(hi) else ""
            parts.append(
                f"<tr><td>{r['rank']}{' <span class=tie>tie</span>' if r['tied'] else ''}</td>"
                f"<td class='l'><b>{e(r['tracker'])}</b>{' (submission)' if r['kind'] == 'score' else ''}</td>"
                f"<td>{_f(r['within'], '.3f')}</td><td class='l'>[{_f(lo, '.3f')}, {_f(hi, '.3f')}] {bar}</td>"
                f"<td>{_f(r['median_abs_mm'], '.2f')}</td><td>{_f(r['rmse_mm'], '.2f')}</td><td>{r['n_gross']}</td>"
                f"<td>{r['n']}</td><td>{_f(r['ms_per_frame'], '.2f')}</td><td class='l'>{e(r['run'])}</td>"
                f"<td class='l'><code>{e(str(r['git_revision'])[:12])}</code></td></tr>")
        parts.append("</table>")
    page = out_dir / "leaderboard.html"
    atomic_write_text(page, "\n".join(parts) + "\n")
    return page
