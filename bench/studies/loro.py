"""The default trackers on photographs, leave one rig out (``stripebench loro``): ``results/real_loro.csv``.

A tracker's operating point on photographs was chosen with photographs in the tuning procedures' real group
(``stripebench tune threshold``: the threshold family's detection, which ``com_bg`` shares, Steger's detection
and the ``auto`` colour rule's knee, which every tracker sees a colour photograph through; ``stripebench tune
dp_gap``: ``dp_gap``'s off state and the DP trackers' reporting rule). Its figure on the same photographs says how
well the choice fits them. This study gives the figure it would have on a rig nobody tuned on: every rig of the
real set is tracked with the choices the procedures made without that rig's photographs (their summaries'
``photographs`` block, :meth:`bench.studies.tuning.Tally.judge`), and the rigs' row outcomes are pooled.

Where a procedure kept the choice made on renders alone (the photographs did not improve on it), the default never
depended on the photographs and every rig is tracked with it. A tracker that nothing was chosen for on photographs
(``learned``, trained on renders; h_weight) has its leave-one-rig-out figure equal to its in-sample one, except
through the colour rule.

Columns of the CSV, one row per tracker: ``tracker``, ``f1_loro``, ``false_report_rate_loro``, ``f1_in_sample``
(the committed defaults on every photograph: ``stripebench real``'s pooled figures), ``false_report_rate_in_sample``,
``f1_renders_only``, ``false_report_rate_renders_only`` (the choices made without any photograph: the plain
baseline), ``recall_loro``, ``n_rigs``, ``n_photographs``, ``rigs_moved`` (the rigs tracked with another setting
than the defaults).
"""

from __future__ import annotations

import csv
import io
import json
import pathlib
import sys

import numpy as np

from bench.errors import InputError

__all__ = ["DEFAULT_TUNING", "DEFAULT_OUT", "FIELDS", "parse_setting", "fold_settings", "loro_table", "study"]

#: The committed tuning summaries the study reads (written by ``stripebench tune threshold`` and ``tune dp_gap``;
#: ``summary.json`` of their output folders, copied here when a default is committed).
DEFAULT_TUNING = {"threshold": pathlib.Path("results/tuning/tune_threshold.json"),
                  "dp_gap": pathlib.Path("results/tuning/tune_dp_gap.json")}
DEFAULT_OUT = pathlib.Path("results/real_loro.csv")
FIELDS = ("tracker", "f1_loro", "false_report_rate_loro", "f1_in_sample", "false_report_rate_in_sample",
          "f1_renders_only", "false_report_rate_renders_only", "recall_loro", "n_rigs", "n_photographs", "rigs_moved")
#: Which trackers each procedure's stage chose for, beside those it scored (``com_bg`` shares the family's
#: detection; ``dp8_subpixel`` the DP trackers' reporting rule).
SHARED = {("threshold", "stage1"): ("com_bg",), ("dp_gap", "stage2"): ("dp8_subpixel",)}


def parse_setting(text: str) -> dict:
    """A procedure's setting label as parameters.

    Examples
    --------
    >>> parse_setting("k_sigma=4,prominence=1.1,min_run=5,width_ratio=none")
    {'k_sigma': 4, 'prominence': 1.1, 'min_run': 5, 'width_ratio': None}
    >>> parse_setting("rule=excess")
    {'rule': 'excess'}
    >>> parse_setting("stripe_test=none"), parse_setting("stripe_test=defaults"), parse_setting("stripe_test=a=4,b=none")
    ({'stripe_test': None}, {'stripe_test': {}}, {'stripe_test': {'a': 4, 'b': None}})
    """
    if text.startswith("stripe_test="):  # the stripe question's candidates (bench.studies.tune_threshold.stripe_key)
        rest = text[len("stripe_test="):]
        return {"stripe_test": None if rest == "none" else {} if rest == "defaults" else parse_setting(rest)}
    out = {}
    for part in text.split(","):
        k, _, v = part.partition("=")
        if v == "none":
            out[k] = None
            continue
        try:
            out[k] = int(v)
        except ValueError:
            try:
                out[k] = float(v)
            except ValueError:
                out[k] = v
    return out


def _read(path, what: str) -> dict:
    p = pathlib.Path(path)
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"{str(p)!r}: no such file (the summary.json of `stripebench tune {what}`)") from None
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"{str(p)!r}: not a readable tuning summary ({type(exc).__name__})") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("photographs"), dict):
        raise InputError(f"{str(p)!r}: no `photographs` block (the summary of a `stripebench tune {what}` that "
                         "judged its choices leave one rig out)")
    return doc


def fold_settings(summaries: dict, rigs) -> tuple[dict, list[str]]:
    """What each rig is tracked with, per tracker and for the colour rule.

    Parameters
    ----------
    summaries : dict
        procedure (``threshold``, ``dp_gap``) -> its summary (``photographs``: stage -> a judgement).
    rigs : list of str

    Returns
    -------
    plans : dict
        ``"in_sample"``, ``"renders_only"`` and each rig -> {tracker -> params (dict), ``"colour_rule"`` -> rule}:
        the stages' kept choices, the renders' choices, and each rig's fold's choices (where a stage kept the
        renders' choice, every fold is tracked with it).
    notes : list of str
        Stages whose photographs do not reach every rig (scored on an older set).
    """
    plans = {k: {} for k in ("in_sample", "renders_only", *rigs)}
    notes = []
    for proc, doc in summaries.items():
        for stage, j in doc["photographs"].items():
            scored = sorted(j.get("trackers", {}))
            names = [*scored, *SHARED.get((proc, stage), ())]
            if not names and stage != "stage4":
                continue
            kept_photos = j["kept"] == j["in_sample"] and j["in_sample"] != j["renders_only"]
            missing = [r for r in rigs if r not in j.get("by_rig", {})]
            if kept_photos and missing:
                notes.append(f"{proc} {stage}: no fold for {', '.join(missing)} (the procedure saw another set); "
                             "tracked with its choice made with every photograph")
            choice = {"in_sample": j["kept"], "renders_only": j["renders_only"]}
            for r in rigs:
                choice[r] = j["by_rig"].get(r, j["in_sample"]) if kept_photos else j["kept"]
            for which, label in choice.items():
                params = parse_setting(label)
                if stage == "stage4" and proc == "threshold":
                    plans[which]["colour_rule"] = params["rule"]
                else:  # a tracker's settings gather over the stages that chose for it
                    for n in names:
                        plans[which].setdefault(n, {}).update(params)
    return plans, notes


def _frames(rule, frames_by_name):
    """The photographs' frames as the trackers see them under a colour rule (``None``: the committed one)."""
    from bench.evaluate.pixels import rotate_image
    from bench.studies.tune_threshold import apply_rule

    if rule is None:
        return frames_by_name
    out = {}
    for name, (f, channel) in frames_by_name.items():
        if f.rgb is not None and channel == "auto":
            img = rotate_image(apply_rule(f.rgb, f.laser, rule), f.rotate)
            out[name] = (f.__class__(f.group, f.name, f.kind, img, f.background, f.truth, f.states, f.rgb, f.laser,
                                     f.rotate), channel)
        else:
            out[name] = (f, channel)
    return out


def loro_table(dataset, summaries: dict, tracker_names, *, say=None) -> tuple[list[dict], list[str]]:
    """The rows of ``real_loro.csv`` (module docstring) and the notes to print.

    Parameters
    ----------
    dataset : path
        A real set whose manifest names each photograph's rig.
    summaries : dict
        procedure -> its tuning summary.
    tracker_names : list of str
    say : callable, optional
        Progress lines.
    """
    import trackers

    from bench.evaluate.outcomes import detection_figures
    from bench.store import realset
    from bench.studies.tuning import frame_counts, real_frames
    from bench.evaluate.outcomes import HIT_PX

    say = say or (lambda m: None)
    frames = real_frames(dataset)
    channels = {im.name: im.channel for im in realset.load_dataset(dataset)}
    base = {f.name: (f, channels[f.name]) for f in frames}
    rigs = sorted({f.kind for f in frames})
    plans, notes = fold_settings(summaries, rigs)
    from bench.evaluate.colour import AUTO_KNEE

    committed_rule = AUTO_KNEE  # what the manifest's `auto` channel applies (stripebench real's frames)
    cache: dict = {}
    views: dict = {}

    def counts(name, params, rule, rig):
        """Per-photograph counts of one tracker setting on one rig's photographs (cached)."""
        key = (name, json.dumps(params, sort_keys=True), str(rule), rig)
        if key not in cache:
            if rule not in views:
                views[rule] = _frames(None if rule == committed_rule else rule, base)  # the manifest's frames
            view = views[rule]
            t = trackers.make(name, **params)
            c = np.zeros(6, dtype=np.int64)
            for f, _ in (v for v in view.values() if v[0].kind == rig):
                c += frame_counts(f.track(t), f, HIT_PX)  # its image, laser-off frame and colour evidence
            cache[key] = c
        return cache[key]

    rows = []
    for name in tracker_names:
        say(f"loro: {name}")
        made = trackers.make(name).get_params()

        def same(params, rule):
            """Whether a setting is the committed default's (then stripebench real's own counts serve)."""
            return all(made.get(k) == v for k, v in params.items()) and rule == committed_rule

        kept, kept_rule = plans["in_sample"].get(name, {}), plans["in_sample"].get("colour_rule", committed_rule)
        if not same(kept, kept_rule):
            def label(params, rule):
                return ", ".join([*(f"{k}={v}" for k, v in params.items()), f"colour rule {rule}"])

            notes.append(f"{name}: the procedures keep {label(kept, kept_rule)}; the committed default is "
                         f"{label({k: made.get(k) for k in kept}, committed_rule)} (commit the procedures' choice, or "
                         "their summaries are of another run)")
        total = {k: np.zeros(6, dtype=np.int64) for k in ("in_sample", "loro", "renders_only")}
        moved = []
        for r in rigs:
            total["in_sample"] += counts(name, {}, committed_rule, r)
            p, rule = plans[r].get(name, {}), plans[r].get("colour_rule", committed_rule)
            if not same(p, rule):
                moved.append(r)
            total["loro"] += counts(name, {} if same(p, rule) else p, rule, r)
            p, rule = plans["renders_only"].get(name, {}), plans["renders_only"].get("colour_rule", committed_rule)
            total["renders_only"] += counts(name, {} if same(p, rule) else p, rule, r)
        fig = {k: detection_figures(v) for k, v in total.items()}
        rows.append({"tracker": name, "f1_loro": fig["loro"]["f1"],
                     "false_report_rate_loro": fig["loro"]["false_report_rate"],
                     "f1_in_sample": fig["in_sample"]["f1"],
                     "false_report_rate_in_sample": fig["in_sample"]["false_report_rate"],
                     "f1_renders_only": fig["renders_only"]["f1"],
                     "false_report_rate_renders_only": fig["renders_only"]["false_report_rate"],
                     "recall_loro": fig["loro"]["recall"], "n_rigs": len(rigs), "n_photographs": len(frames),
                     "rigs_moved": " ".join(moved)})
    return rows, notes


def _csv(rows) -> str:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(FIELDS), lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: (f"{v:.4f}" if isinstance(v, float) else v) for k, v in r.items()})
    return buf.getvalue()


def study(*, dataset=None, threshold=DEFAULT_TUNING["threshold"], gap=DEFAULT_TUNING["dp_gap"],
          out=DEFAULT_OUT, trackers=None, quiet: bool = False) -> int:
    """``stripebench loro``: every default tracker on a real set (default the shipped one), leave one rig out,
    from the tuning procedures' committed summaries; writes ``out`` (CSV, :data:`FIELDS`) and prints the table.

    Raises
    ------
    bench.errors.InputError
        A tuning summary is missing or holds no leave-one-rig-out judgement; the real set breaks the layout.
    """
    import trackers as registry

    from bench.store import realset
    from bench.store.files import atomic_write_text

    dataset = realset.SHIPPED if dataset is None else pathlib.Path(dataset)
    summaries = {"threshold": _read(threshold, "threshold"), "dp_gap": _read(gap, "dp_gap")}
    names = list(trackers) if trackers else registry.available()
    say = (lambda m: None) if quiet else (lambda m: print(m, file=sys.stderr, flush=True))
    rows, notes = loro_table(dataset, summaries, names, say=say)
    for n in notes:
        print(f"stripebench loro: {n}", file=sys.stderr)
    atomic_write_text(out, _csv(rows))
    print(f"{'tracker':<14}{'F1 loro':>9}{'FRR loro':>10}{'F1 in sample':>14}{'FRR in sample':>15}"
          f"{'F1 renders only':>17}   rigs tracked otherwise")
    for r in rows:
        print(f"{r['tracker']:<14}{r['f1_loro']:>9.3f}{r['false_report_rate_loro']:>10.3f}{r['f1_in_sample']:>14.3f}"
              f"{r['false_report_rate_in_sample']:>15.3f}{r['f1_renders_only']:>17.3f}   {r['rigs_moved'] or '-'}")
    print(f"{len(rows)} trackers, {rows[0]['n_photographs'] if rows else 0} photographs from "
          f"{rows[0]['n_rigs'] if rows else 0} rigs: {out}")
    return 0
