"""``stripebench leaderboard``: the trackers of comparable runs ranked per condition, one HTML page and a CSV.

Runs are comparable when :func:`bench.run.gate.comparability` finds no
difference among :data:`bench.run.gate.COMPARED_KEYS` (render size and spp,
experiments, seed) and they scored the same frames (:func:`frames_of`: each
experiment's mirror angles as the summary's ``scans`` list them; a scored
submission of ``--split dev`` or ``test`` scores a part, and a frame set's test
frames are rendered at angles of their own, :func:`bench.run.export.test_frame`);
otherwise the page is refused in one line. The runs
are read in one order whatever the order of the arguments (scored submissions
first, then by folder path: :func:`canonical_order`), so the board does not
depend on it. Each row says where it comes from (:data:`ORIGINS`: a submission,
a built-in tracker of a scored submission's run, a built-in tracker of a run).
Every distinct tracker setting enters once: a label whose setting (name,
parameters, restore; a submission's checksum) was already entered by an earlier
run is dropped, and a label that another run used for another setting enters
again as ``label [run]``; each such decision, and a run that contributes nothing
(no conditions in its summary), is one line of ``notes``. Per condition,
trackers are ranked (``rank_by``, :data:`RANK_BY`) by default by F1 over rows
(:mod:`bench.evaluate.outcomes`: hits against misses, wrong columns and false
reports alike, every row of the frames), or by ``ap`` (the average precision of
the tracker's score), each with its bootstrap interval over frames, or by the
fraction of sample points within ±5 mm (``within``, the paper's reading, missing
points counted as misses) with its Wilson 95 % interval. ``within`` cannot see a
false report (its sample points lie on the object's stripe), so the false-report
rate and the false 3-D points per scan stand beside every ranking. A tracker whose
interval overlaps that of the first tracker of the rank above it (the rank's
leader) is marked tied and shares that rank (the report's rule: intervals
overlap => tie; comparing with the leader, not the neighbour, keeps ties from
chaining down a table of small steps, :func:`rank_with_ties`). Beside it: median |error|,
RMSE, gross errors, ms per frame (the mean over the condition's experiments
of ``timings.csv``) and the run and code revision the entry comes from.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

from bench.errors import InputError
from bench.report.html import esc, fixed, page
from bench.run import gate
from bench.store.files import atomic_write_text
from bench.store.runfolder import RunFolderError, load_metrics, load_summary

__all__ = ["LeaderboardError", "leaderboard_rows", "build_leaderboard", "rank_with_ties", "COLUMNS", "RANK_BY",
           "ORIGINS", "settings_of", "split_of", "frames_of", "canonical_order", "DEFAULT_RANK_BY"]

COLUMNS = ("condition", "rank", "tied", "rank_by", "tracker", "within", "within_low", "within_high", "median_abs_mm",
           "rmse_mm", "n_gross", "n", "f1", "f1_low", "f1_high", "ap", "ap_low", "ap_high", "false_report_rate",
           "false_points_per_scan", "ms_per_frame", "run", "kind", "origin", "git_revision")
#: Where a row comes from.
ORIGINS = ("submission", "built-in (scored run)", "built-in (run)")
#: What a leaderboard can rank by: F1 or AP over rows (both halves of detection), or the ±5 mm fraction of
#: sample points (the paper's reading, blind to false reports).
RANK_BY = ("f1", "ap", "within")
#: The default ranking: F1 over rows, which prices a miss and a false report alike.
DEFAULT_RANK_BY = "f1"
_NAN = float("nan")


_TRACK_PX = 200  # width of the interval track on the page


class LeaderboardError(InputError):
    """Runs that cannot share a leaderboard; one line."""


def _group_of(summary: dict, cond: dict, robust_groups: set) -> str | None:
    g = f"condition:{cond['condition']}"
    if g in robust_groups:
        return g
    if len(cond["experiments"]) == 1 and cond["experiments"][0] in robust_groups:
        return cond["experiments"][0]
    return None


def settings_of(summary: dict) -> dict[str, tuple[str, str]]:
    """label -> (origin, setting) of every tracker of a run's summary: the setting is a canonical
    JSON text of its name, parameters and restore (a submission: its checksum), which says whether
    two runs' labels are the same tracker.

    Examples
    --------
    >>> s = {"kind": "run", "config": {"trackers": ["dp4", {"label": "iso", "name": "dp4",
    ...                                                     "params": {"h_weight": 1.0}}]}}
    >>> settings_of(s)["iso"]
    ('built-in (run)', '{"label": "iso", "name": "dp4", "params": {"h_weight": 1.0}}')
    """
    import json

    origin = "built-in (scored run)" if summary.get("kind") == "score" else "built-in (run)"
    out = {}
    sub = summary.get("submission")
    alone = summary.get("kind") == "score" and isinstance(sub, dict) and sub.get("alone")
    for t in [] if alone else (summary.get("config") or {}).get("trackers", []):  # alone: none of them ran
        spec = {"label": t, "name": t} if isinstance(t, str) else dict(t)
        label = spec.get("label", spec.get("name"))
        spec.pop("timeout_s", None), spec.pop("isolate", None)  # how it runs, not what it computes
        spec["label"] = label
        out[label] = (origin, json.dumps(spec, sort_keys=True))
    if summary.get("kind") == "score" and isinstance(sub, dict):
        out[sub.get("label")] = ("submission", json.dumps({"submission": sub.get("checksum")}))
    return out


def split_of(summary: dict) -> tuple[str, int | None]:
    """Which frames a run scored: ``("all", None)`` for a run, else a scored submission's ``--split``
    and its number of frames.

    >>> split_of({"kind": "run"}), split_of({"kind": "score", "submission": {"split": "test", "frames": 12}})
    (('all', None), ('test', 12))
    """
    sub = summary.get("submission") if summary.get("kind") == "score" else None
    if not isinstance(sub, dict):
        return "all", None
    return str(sub.get("split", "all")), sub.get("frames")


def frames_of(summary: dict) -> tuple:
    """The frames a run scored: ``(experiment, angles)`` per scan, from its summary's ``scans``
    (``angles_deg``; a summary written without them: its split, :func:`split_of`). Two runs of
    comparable configurations scored the same frames when these are equal.

    >>> frames_of({"kind": "run", "scans": [{"experiment": "e", "angles_deg": [1.0, 2.0]}]})
    (('e', (1.0, 2.0)),)
    """
    scans = summary.get("scans") or []
    if scans and all(isinstance(x, dict) and isinstance(x.get("angles_deg"), list) for x in scans):
        return tuple((str(x.get("experiment")), tuple(float(a) for a in x["angles_deg"])) for x in scans)
    return ("split",) + split_of(summary)


def canonical_order(loaded: list) -> list:
    """``(path, summary, ...)`` tuples in the order a board reads them: scored submissions first (a board
    is about them: a built-in tracker that a submission's run re-tracked is kept with that run), then by
    resolved folder path. The board is the same whatever the order of the arguments."""
    return sorted(loaded, key=lambda x: (x[1].get("kind") != "score", str(Path(x[0]).resolve())))


def leaderboard_rows(runs, rank_by: str = DEFAULT_RANK_BY, notes: list | None = None) -> list[dict]:
    """One row per condition x tracker of the runs (:data:`COLUMNS`), ranked by ``rank_by`` (:data:`RANK_BY`).

    ``notes`` (a list), if given, receives one line per setting dropped or renamed and per run
    that contributes nothing, with the reason. The runs are read in :func:`canonical_order`.

    Raises
    ------
    LeaderboardError
        A run is not a finished run or scored submission, two runs are not comparable, or they
        scored different frames (:func:`split_of`).
    """
    if rank_by not in RANK_BY:
        raise LeaderboardError(f"--rank-by must be one of {', '.join(RANK_BY)}, got {rank_by!r}")
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
    loaded = canonical_order(loaded)
    first = loaded[0][1]["config"]
    for path, s, _ in loaded[1:]:
        diff = gate.comparability(first, s["config"])
        if diff:
            raise LeaderboardError(f"{str(path)!r} is not comparable with {str(loaded[0][0])!r}: they differ in "
                                   f"{'; '.join(diff)}")
    if len({frames_of(s) for _, s, _ in loaded}) > 1:
        said = "; ".join(f"{str(p)!r}: {_split_text(s)}" for p, s, _ in loaded)
        raise LeaderboardError(f"the runs scored different frames, so their figures cannot share a board ({said}); "
                               "score every submission on the same frames (the same frame set and --split; a frame set's test "
                               "frames are not a run's, `export --test-fraction 0` exports the run's own)")
    notes = [] if notes is None else notes
    entered: dict[str, tuple[str, str]] = {}  # label -> (setting, run) of the first entry
    seen, per_cond = set(), {}
    for path, s, m in loaded:
        if not s.get("conditions"):
            notes.append(f"{path.name}: its summary.json lists no conditions; it adds nothing to the board")
            continue
        shown = {}  # label in this run -> label on the board (None: dropped)
        for label, (origin, setting) in settings_of(s).items():
            first = entered.get(label)
            if first is None:
                entered[label] = (setting, path.name)
                shown[label] = label
            elif first[0] == setting:
                shown[label] = None
                notes.append(f"{label} of {path.name}: the same setting as {first[1]}'s {label}; kept {first[1]}'s")
            else:
                shown[label] = f"{label} [{path.name}]"
                notes.append(f"{label} of {path.name} is another setting than {first[1]}'s {label}: "
                             f"shown as {shown[label]!r}")
        origins = {label: o for label, (o, _) in settings_of(s).items()}
        rob = {(x["group"], x["tracker"]): x for x in s.get("robust", [])}
        det = {(x["group"], x["tracker"]): x for x in s.get("detection", [])}
        groups = {g for g, _ in rob}
        for cond in s.get("conditions", []):
            g = _group_of(s, cond, groups)
            if g is None:
                continue
            mm = m[(m["region"] == "all") & m["experiment"].isin(cond["experiments"])]
            for (gg, label), x in rob.items():
                board = shown.get(label, label)
                if gg != g or board is None or (cond["condition"], board) in seen:
                    continue
                seen.add((cond["condition"], board))
                t = mm[mm["tracker"] == label]["ms_per_frame"].astype(float)
                ms = float(t.mean()) if t.notna().any() else float("nan")
                d = det.get((f"condition:{cond['condition']}", label), {})
                per_cond.setdefault(cond["condition"], []).append({
                    "condition": cond["condition"], "tracker": board, "within": x["within"],
                    "within_low": x["within_low"], "within_high": x["within_high"],
                    "median_abs_mm": x["median_abs_mm"], "rmse_mm": x["rmse_mm"], "n_gross": x["n_gross"],
                    "n": x["n"], "ms_per_frame": ms, "run": path.name, "kind": s["kind"],
                    "origin": origins.get(label, "built-in (run)"),
                    "git_revision": s.get("git_revision", ""), "rank_by": rank_by,
                    **{f"{k}{suf}": d.get(f"{k}{src}", _NAN) for k in ("f1", "ap")
                       for suf, src in (("", ""), ("_low", "_lo"), ("_high", "_hi"))},
                    "false_report_rate": d.get("false_report_rate", _NAN),
                    "false_points_per_scan": d.get("false_points_per_scan", _NAN)})
    out = []
    for rows in per_cond.values():
        out += rank_with_ties(rows, rank_by)
    return [{k: r[k] for k in COLUMNS} for r in out]


def _n_frames(summary: dict) -> int:
    return sum(int(x.get("frames", 0)) for x in summary.get("scans") or [] if isinstance(x, dict))


def _split_text(summary: dict) -> str:
    what = "a run" if summary.get("kind") != "score" else f"--split {split_of(summary)[0]}"
    return f"{what} ({_n_frames(summary)} frames)"


def rank_with_ties(rows: list[dict], key: str = "within") -> list[dict]:
    """``rows`` sorted by ``key`` (best first, then by ``tracker``), each with ``rank`` and ``tied``.

    A row is tied, and shares the rank, when its interval reaches the lower end
    of the interval of the rank's leader (the first row holding that rank);
    otherwise it starts a new rank at its position (1-based). A NaN value sorts last and never ties.

    Parameters
    ----------
    rows : list of dict
        Each with ``tracker``, ``key`` and its interval ``<key>_low``, ``<key>_high`` (fractions).
    key : str
        The figure ranked by (higher is better).

    Examples
    --------
    Each neighbour overlaps the next, but c does not overlap the leader a, so c starts rank 3:

    >>> rows = [{"tracker": t, "within": w, "within_low": w - 0.06, "within_high": w + 0.06}
    ...         for t, w in (("a", 0.95), ("b", 0.88), ("c", 0.81), ("d", 0.76))]
    >>> [(r["tracker"], r["rank"], r["tied"]) for r in rank_with_ties(rows)]
    [('a', 1, False), ('b', 1, True), ('c', 3, False), ('d', 3, True)]
    """
    lo, hi = f"{key}_low", f"{key}_high"
    rows = sorted(rows, key=lambda r: (-(r[key] if _ok(r[key]) else -1.0), r["tracker"]))
    out, leader, rank = [], None, 0
    for i, r in enumerate(rows):
        tied = leader is not None and _ok(r[hi]) and _ok(leader[lo]) and r[hi] >= leader[lo]
        if not tied:
            leader, rank = r, i + 1
        out.append({**r, "rank": rank, "tied": bool(tied)})
    return out


_RANK_HEAD = {"within": "±5 mm", "f1": "F1", "ap": "AP"}
_RANK_TEXT = {"within": "the fraction of sample points within ±5 mm (the paper's reading; its points lie on the "
                        "object's stripe, so it cannot see a false report: read the false reports beside it)",
              "f1": "F1 over rows (hits against misses, wrong columns and false reports alike)",
              "ap": "AP over rows (the tracker's score ranking its reports)"}


def _ok(v) -> bool:
    return isinstance(v, (int, float)) and math.isfinite(v)


def _first_summary(runs) -> dict:
    return load_summary(list(runs)[0])


def build_leaderboard(runs, out_dir, rank_by: str = DEFAULT_RANK_BY, notes: list | None = None) -> Path:
    """Write ``leaderboard.html`` and ``leaderboard.csv`` into ``out_dir``, ranked by ``rank_by``
    (:data:`RANK_BY`); returns the page. ``notes``: as :func:`leaderboard_rows` (also on the page).

    Raises
    ------
    LeaderboardError
        See :func:`leaderboard_rows`.
    """
    notes = [] if notes is None else notes
    rows = leaderboard_rows(runs, rank_by, notes)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    atomic_write_text(out_dir / "leaderboard.csv", buf.getvalue())
    e = esc
    css = ("table{margin-bottom:2em;font-size:13px}td,th{border:none;border-bottom:1px solid #ddd;padding:4px 10px}"
           "p{max-width:60em}td.l,th.l{text-align:left}th{white-space:nowrap;background:none}"
           f".track{{position:relative;display:inline-block;width:{_TRACK_PX}px;height:12px;background:#eee;"
           "vertical-align:middle}.bar{position:absolute;top:0;height:12px;background:#7b9}"
           ".mark{position:absolute;top:-2px;width:2px;height:16px;background:#145}"
           ".scale{font-weight:normal;color:#666;font-size:85%}.tie{color:#a60}")
    parts = ["<h1>stripebench leaderboard</h1>",
             f"<p>{len(list(runs))} comparable run(s), each of the same {_n_frames(_first_summary(runs))} frames. "
             f"Ranked per condition by {_RANK_TEXT[rank_by]} "
             "(its 95 % interval drawn as a bar with the estimate marked). <span class='tie'>tie</span>: its "
             "interval overlaps that of the rank's first tracker, so it shares that rank. ±5 mm: the fraction of "
             "sample points within ±5 mm (Wilson interval; missing points count as misses). F1 and AP over "
             "rows: every row is a hit, wrong, missed, false (a report where there is no stripe) or quiet; AP "
             "ranks the reports by the tracker's own score. False points: reports on stripe-less rows per "
             "scan, each a 3-D point where there is no surface. Times are ms per frame (a "
             "submission's own times.csv, else the harness's clock; machine dependent).</p>"]
    if notes:
        parts.append("<p>What was left out or renamed:</p><ul>" + "".join(f"<li>{e(n)}</li>" for n in notes) + "</ul>")
    for cond in dict.fromkeys(r["condition"] for r in rows):
        crows = [x for x in rows if x["condition"] == cond]
        lows = [x[f"{rank_by}_low"] for x in crows if _ok(x[f"{rank_by}_low"])]
        start = min(0.9, math.floor(10 * min(lows)) / 10) if lows else 0.0  # the track spans [start, 1]
        parts.append(f"<h2>{e(cond)}</h2><table><tr><th>rank</th><th class='l'>tracker</th>"
                     f"<th>{_RANK_HEAD[rank_by]}</th><th class='l'>95 % interval</th><th class='l'>interval "
                     f"<span class='scale'>(track {start:.1f} to 1)</span></th>"
                     + "".join(f"<th>{_RANK_HEAD[k]}</th>" for k in RANK_BY if k != rank_by)
                     + "<th>false reports</th><th>false points/scan</th><th>median |e| mm</th><th>RMSE mm</th>"
                     "<th>gross</th><th>n</th><th>ms/frame</th><th class='l'>run</th><th class='l'>code</th></tr>")
        for r in crows:
            lo, hi = r[f"{rank_by}_low"], r[f"{rank_by}_high"]
            bar = ""
            if _ok(lo) and _ok(hi) and _ok(r[rank_by]):
                x0, x1, xm = (_TRACK_PX * (v - start) / (1 - start) for v in (lo, hi, r[rank_by]))
                bar = (f"<span class='track'><span class='bar' style='left:{x0:.0f}px;width:{max(1.0, x1 - x0):.0f}px'>"
                       f"</span><span class='mark' style='left:{xm - 1:.0f}px'></span></span>")
            parts.append(
                f"<tr><td>{r['rank']}{' <span class=tie>tie</span>' if r['tied'] else ''}</td>"
                f"<td class='l'><b>{e(r['tracker'])}</b> <span class='scale'>{e(r['origin'])}</span></td>"
                f"<td>{fixed(r[rank_by], '.3f')}</td><td class='l'>[{fixed(lo, '.3f')}, {fixed(hi, '.3f')}]</td>"
                f"<td class='l'>{bar}</td>"
                + "".join(f"<td>{fixed(r[k], '.3f')}</td>" for k in RANK_BY if k != rank_by)
                + f"<td>{fixed(r['false_report_rate'], '.3f')}</td><td>{fixed(r['false_points_per_scan'], '.0f')}</td>"
                f"<td>{fixed(r['median_abs_mm'], '.2f')}</td><td>{fixed(r['rmse_mm'], '.2f')}</td><td>{r['n_gross']}</td>"
                f"<td>{r['n']}</td><td>{fixed(r['ms_per_frame'], '.2f')}</td><td class='l'>{e(r['run'])}</td>"
                f"<td class='l'><code>{e(str(r['git_revision'])[:12])}</code></td></tr>")
        parts.append("</table>")
    path = out_dir / "leaderboard.html"
    atomic_write_text(path, page("stripebench leaderboard", "\n".join(parts) + "\n", css=css))
    return path
