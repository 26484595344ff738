"""The frames every detection-tuning procedure scores, and its one objective.

The operating points of the trackers (the threshold family's detection, Steger's
ridge strength, the DP trackers' reporting rule, ``dp_gap``'s off state) are chosen
by ``stripebench tune threshold`` and ``stripebench tune dp_gap`` on three groups
of frames, none of which the paper experiment uses:

``synthetic``
    seeded numpy photographs of the failure classes (:mod:`bench.studies.hard_frames`,
    seeds of the profile, never 0), every frame with stripe-less stretches of each
    kind (past an edge, shadow, mirror, dark void, textured void);
``renders``
    scans of the profile's experiments (spheres and planes, never the paper's cone
    or hand, seed of the profile, never 0), rendered and cached like any run;
``real``
    the shipped photographs (:data:`bench.store.realset.SHIPPED`) with their
    references' row states (explicit, or the fallback rule).

The objective (:func:`objective`) prices a miss and a false report alike: a
setting's row outcomes are pooled over the frames of each group and the trackers
scored, each group's F1 over rows is taken, and the objective is their mean, so
each group weighs the same whatever its number of frames.

One eligibility rule goes with it: a setting that reports nothing at all on a frame
whose brightest pixel per row is right on at least :data:`EASY_ARGMAX` of its stripe
rows goes *blind* where the stripe is plain to see. A photograph's blindness
disqualifies: only the settings blind on the fewest photographs (none, where one
setting manages that) are eligible, and among them those blind on the fewest such
frames of the other groups (:meth:`Tally.eligible`): a tracker that says "no stripe"
must not say it there, and least of all on a photograph.

A ceiling may go with them (``max_false_rate`` of a profile), after a photograph's blindness and before the
other groups' blindness: a setting under which a tracker reports on more than that share of the seen
photographs' stripe-less rows is not eligible where another setting keeps every tracker within it
(:meth:`Tally.loud`). Both photograph rules are targets a default tracker must meet on rigs nobody tuned on;
the other groups' blindness is the procedure's own caution.

A choice made on photographs is judged leave one rig out (:meth:`Tally.judge`, :mod:`bench.evaluate.loro`): each
rig's photographs are scored under the choice made without them, and that figure is set against the choice made
on the renders and synthetic frames alone (the plain baseline). A stage keeps its choice made with every
photograph only where the photographs, so judged, improve on the baseline; else the renders' choice.
"""

from __future__ import annotations

import csv
import json
import pathlib
import sys
from dataclasses import dataclass

import numpy as np

from bench.evaluate.outcomes import COUNT_KEYS, detection_figures, outcome_counts, row_outcomes, truth_states

__all__ = ["TuningFrame", "GROUPS", "EASY_ARGMAX", "synthetic_frames", "real_frames", "rendered_frames",
           "frame_counts", "objective", "group_figures", "counts_record", "Tally", "within_ceiling", "judged_lines",
           "run_study", "RECORD_FIELDS", "write_records"]

#: The groups of tuning frames, in the order they are reported.
GROUPS = ("synthetic", "renders", "real")
#: A frame is plain to see when its brightest pixel per row is within the hit rule of the stripe on at
#: least this fraction of its stripe rows; reporting nothing on such a frame makes a setting ineligible.
EASY_ARGMAX = 0.75


@dataclass(frozen=True, eq=False)
class TuningFrame:
    """One tuning frame: what a tracker sees, and the truth it is scored on.

    Attributes
    ----------
    group : str
        One of :data:`GROUPS`.
    name : str
        Unique within the group (``printed-100``, ``sphere-patchy/3``, ``al_room0``).
    kind : str
        What the frame stands for within its group (hard-frame kind, experiment, rig).
    image : ndarray, shape (H, W)
        The frame as the trackers get it (uint8 or float64).
    background : ndarray, shape (H, W), or None
        Its laser-off frame, if any.
    truth : ndarray of float64, shape (H,)
        The stripe's column per row (px), NaN where there is none.
    states : ndarray of int8, shape (H,)
        Row states (:data:`bench.evaluate.outcomes.STATES`).
    rgb : ndarray or None
        The colour photograph (H0, W0, 3) before the channel rule, where there is one.
    laser : str
        The laser's colour (for the colour rule).
    rotate : int
        Degrees the colour photograph is turned to give ``image``'s orientation.
    """

    group: str
    name: str
    kind: str
    image: np.ndarray
    background: np.ndarray | None
    truth: np.ndarray
    states: np.ndarray
    rgb: np.ndarray | None = None
    laser: str = "red"
    rotate: int = 0

    @property
    def colour(self) -> np.ndarray | None:
        """The colour evidence the trackers get with the frame (:func:`trackers.colour_evidence` of its
        colour photograph, turned as the frame is), (H, W) float64 in [0, 1]; None without colour (no
        photograph, or a grey one). Computed once."""
        if "_colour" not in self.__dict__:
            from bench.run.camera_view import colour_of

            ev = colour_of(self.rgb, self.laser, self.rotate)
            if ev is not None and ev.shape != self.image.shape:  # a photograph that is not the frame's pixels
                ev = None
            self.__dict__["_colour"] = ev
        return self.__dict__["_colour"]

    def track(self, tracker):
        """``tracker``'s columns (H,) on this frame: its image, laser-off frame and colour evidence."""
        return tracker.track(self.image, background=self.background, colour=self.colour).columns

    @property
    def easy(self) -> bool:
        """Whether the frame's brightest pixel per row is right on at least :data:`EASY_ARGMAX` of its
        stripe rows (:func:`bench.studies.hard_frames.argmax_right`, computed once)."""
        cached = self.__dict__.get("_easy")
        if cached is None:
            from bench.studies.hard_frames import argmax_right

            rows = self.states == 1
            cached = bool(rows.any() and argmax_right(self.image[rows], self.truth[rows]) >= EASY_ARGMAX)
            self.__dict__["_easy"] = cached
        return cached


def synthetic_frames(kinds, seeds, *, background: bool = False) -> list[TuningFrame]:
    """The hard frames of ``kinds`` x ``seeds`` (their laser channel, as a mono camera behind a filter
    sees it; with ``background`` their laser-off frame too)."""
    from bench.studies.hard_frames import hard_frame

    out = []
    for k in kinds:
        for s in seeds:
            f = hard_frame(k, int(s))
            out.append(TuningFrame("synthetic", f"{k}-{s}", k, f.laser_channel,
                                   f.laser_channel_off if background else None, f.truth, truth_states(f.truth),
                                   f.rgb, f.laser, 0))
    return out


def real_frames(root=None) -> list[TuningFrame]:
    """The photographs of a real set (default the shipped one) as ``stripebench real`` gives them
    to the trackers, with their references' states; ``kind`` is the photograph's rig
    (:attr:`bench.store.realset.RealImage.rig`)."""
    from bench.store import realset

    out = []
    for im in realset.load_dataset(realset.SHIPPED if root is None else root):
        frame, bg, original, _ = im.load()
        cols, states = im.reference(frame.shape)
        out.append(TuningFrame("real", im.name, im.rig, frame, bg, cols, states,
                               original if np.asarray(original).ndim == 3 else None, im.laser_colour,
                               im.rotate_deg))
    return out


def rendered_frames(experiments, render: dict, seed: int, *, progress: bool = True) -> list[TuningFrame]:
    """Every frame of a scan of each experiment (renders come from the scenes' disk cache when present).

    Parameters
    ----------
    experiments : list of dict
        ``scene``, ``material`` and scene overrides (a tuning profile's ``experiments``).
    render : dict
        ``width``, ``height``, ``spp``, ``n_angles``.
    seed : int
        The renders' seed (never the paper run's 0).
    progress : bool
        One line per experiment on stderr.
    """
    import scenes

    from bench.run.camera_view import tracker_images

    out = []
    for k, e in enumerate(experiments):
        overrides = {key: v for key, v in e.items() if key not in ("scene", "material")}
        scene = scenes.make(e["scene"], material=e["material"], seed=seed, width=render["width"],
                            height=render["height"], spp=render["spp"], **overrides)
        angles = scene.object.default_angles(scene.rig.zeta_deg, render["n_angles"])
        key = "".join([f"{e['scene']}-{e['material']}"] + [f"_{a}={b}" for a, b in sorted(overrides.items())])
        if progress:
            print(f"renders [{k + 1}/{len(experiments)}] {key}: {len(angles)} frames", file=sys.stderr, flush=True)
        for i, a in enumerate(angles):
            frame = scene.render(float(a), spp=render["spp"], seed=seed)
            image, bg = tracker_images(frame, scene.params)
            truth = np.asarray(frame.truth.columns, dtype=np.float64)
            out.append(TuningFrame("renders", f"{key}/{i}", key, image, bg, truth, truth_states(truth)))
    return out


def frame_counts(columns, frame: TuningFrame, hit_px: float) -> np.ndarray:
    """The row-outcome counts (in :data:`bench.evaluate.outcomes.OUTCOMES` order) of a tracker's columns on a frame."""
    codes = row_outcomes(columns, frame.truth, frame.states, hit_px)
    return outcome_counts(codes, axis=0)


def group_figures(counts: dict) -> dict:
    """Precision, recall, F1 and the false-report rate of each group's pooled counts.

    Parameters
    ----------
    counts : dict
        group -> counts (6,) in :data:`bench.evaluate.outcomes.OUTCOMES` order.

    Examples
    --------
    >>> group_figures({"real": np.array([8, 1, 1, 2, 8, 0])})["real"]["f1"]
    0.7619047619047619
    """
    return {g: detection_figures(np.asarray(c)) for g, c in counts.items()}


def objective(counts: dict) -> float:
    """The tuning objective: the mean over groups of each group's F1 over rows (pooled over its
    frames and trackers); groups without a stripe row or a report are left out (NaN if all are).

    Examples
    --------
    >>> objective({"synthetic": np.array([9, 0, 1, 0, 10, 0]), "real": np.array([5, 0, 5, 5, 5, 0])})
    0.7236842105263157
    """
    f1 = [v["f1"] for v in group_figures(counts).values() if np.isfinite(v["f1"])]
    return float(np.mean(f1)) if f1 else float("nan")


def counts_record(counts) -> dict:
    """``{n_hit: ..., n_unknown: ...}`` of a counts array (for the tables the procedures write)."""
    return {k: int(v) for k, v in zip(COUNT_KEYS, np.asarray(counts))}


class Tally:
    """Row-outcome counts of one stage of a procedure, per setting, tracker, group and kind.

    Examples
    --------
    >>> f = TuningFrame("real", "a", "rig", np.zeros((2, 4)), None, np.array([1.0, np.nan]),
    ...                 np.array([1, 0], np.int8))
    >>> t = Tally(1, 3.0)
    >>> t.add("k=1", "threshold", f, np.array([1.5, 2.0]))
    >>> t.objective("k=1"), t.records()[0]["n_false"]
    (0.6666666666666666, 1)
    """

    def __init__(self, stage: int, hit_px: float, max_false_rate: float | None = None):
        self.stage = stage
        self.hit_px = hit_px
        #: the false-report ceiling of :meth:`eligible` and :meth:`judge` (None: none)
        self.max_false_rate = max_false_rate
        self.counts: dict = {}
        self.blind: dict = {}  # setting -> names of the plain frames on which a tracker reported nothing
        self._blind_at: dict = {}  # setting -> (group, kind) of each of those frames
        self._keys: dict = {}  # setting -> its keys of `counts`

    def add(self, setting: str, tracker: str, frame, columns) -> None:
        """Count the outcomes of ``columns`` (H,) on ``frame`` under ``setting`` and ``tracker``."""
        key = (setting, tracker, frame.group, frame.kind)
        c = frame_counts(columns, frame, self.hit_px)
        if key not in self.counts:
            self._keys.setdefault(setting, []).append(key)
        self.counts[key] = self.counts.get(key, 0) + c
        blind = self.blind.setdefault(setting, [])
        at = self._blind_at.setdefault(setting, [])
        if np.isnan(columns).all() and frame.easy:
            blind.append(f"{tracker} on {frame.group}/{frame.name}")
            at.append((frame.group, frame.kind))

    @staticmethod
    def _seen(group: str, kind: str, held_out, photographs: bool) -> bool:
        """Whether a choice may see the frames of ``group``/``kind``: every frame but the photographs of the
        held-out rig, and no photograph at all without ``photographs``."""
        return group != "real" or (photographs and kind != held_out)

    def eligible(self, scores: dict, key, *, held_out=None, photographs: bool = True) -> dict:
        """``scores`` (setting -> objective) restricted by the photographs' two rules, then the other groups':

        1. the settings that went blind on the fewest plain photographs (none, where one setting manages that;
           ``key(setting)`` names a setting as :meth:`add` got it): a photograph's blindness disqualifies whatever
           the other groups say;
        2. with a ceiling (:attr:`max_false_rate`), among those, the settings that keep every tracker within it on
           the photographs (:meth:`loud`), where some setting does;
        3. among those, the settings blind on the fewest plain frames in all (none, where some setting never is).

        A frame on which every setting goes blind disqualifies none of them (:meth:`unavoidable` names the
        photographs among those). Frames the choice may not see (``held_out``, ``photographs``: as
        :meth:`objective`) do not count."""
        def count(s, photos_only):
            return sum(self._seen(g, k, held_out, photographs) and (g == "real" or not photos_only)
                       for g, k in self._blind_at.get(key(s), ()))

        photos = {s: count(s, True) for s in scores}
        least = min(photos.values(), default=0)
        keep = [s for s in scores if photos[s] == least]
        if photographs:  # the photographs' two rules first, then the other groups' blindness
            keep = [s for s in keep if not self.loud(key(s), held_out=held_out)] or keep
        blind = {s: count(s, False) for s in keep}
        fewest = min(blind.values(), default=0)
        return {s: scores[s] for s in keep if blind[s] == fewest}

    def false_rates(self, setting: str, *, held_out=None) -> dict:
        """tracker -> the false-report rate of ``setting`` (as :meth:`add` got it) on the photographs pooled, without
        those of the rig ``held_out`` (NaN where they have no stripe-less row)."""
        pooled: dict = {}
        for key in self._keys.get(setting, ()):
            _, t, g, k = key
            if g == "real" and k != held_out:
                pooled[t] = pooled.get(t, 0) + np.asarray(self.counts[key])
        return {t: detection_figures(c)["false_report_rate"] for t, c in sorted(pooled.items())}

    def loud(self, setting: str, *, held_out=None) -> dict:
        """The trackers whose false-report rate under ``setting`` on the photographs (:meth:`false_rates`) is above
        :attr:`max_false_rate`, with that rate (empty without a ceiling)."""
        if self.max_false_rate is None:
            return {}
        return {t: r for t, r in self.false_rates(setting, held_out=held_out).items() if r > self.max_false_rate}

    def unavoidable(self, setting: str) -> list[str]:
        """The plain photographs on which ``setting`` (as :meth:`add` got it) goes blind: for a chosen
        setting, those on which every setting of the stage does (a procedure prints them)."""
        return [b for b, (g, _) in zip(self.blind.get(setting, ()), self._blind_at.get(setting, ())) if g == "real"]

    def objective(self, setting: str, *, held_out=None, photographs: bool = True) -> float:
        """:func:`objective` of a setting, its counts pooled over its trackers; without the photographs of the rig
        ``held_out``, or, with ``photographs=False``, of every rig (the choice made on renders alone)."""
        by_group: dict = {}
        for key in self._keys.get(setting, ()):
            _, _, g, k = key
            if self._seen(g, k, held_out, photographs):
                by_group[g] = by_group.get(g, 0) + self.counts[key]
        return objective(by_group)

    def rig_counts(self, setting: str, tracker: str | None = None) -> dict:
        """rig -> the photographs' pooled counts (6,) of a setting (over its trackers, or of ``tracker``)."""
        out: dict = {}
        for key in self._keys.get(setting, ()):
            _, t, g, k = key
            if g == "real" and (tracker is None or t == tracker):
                out[k] = out.get(k, 0) + np.asarray(self.counts[key])
        return out

    def judge(self, pick) -> dict:
        """A stage's choice judged on the photographs, leave one rig out (:mod:`bench.evaluate.loro`).

        Parameters
        ----------
        pick : callable
            ``pick(held_out, photographs) -> setting`` (the setting as :meth:`add` got it): the stage's rule,
            scoring with :meth:`objective` and :meth:`eligible` under the same two arguments.

        Returns
        -------
        dict
            ``in_sample`` (chosen with every photograph), ``by_rig`` (held-out rig -> chosen without it),
            ``renders_only`` (chosen without any photograph: the plain baseline), ``kept`` (``in_sample`` where its
            leave-one-rig-out F1 on the photographs beats the renders-only choice's, else ``renders_only``: the
            photographs must earn their say; with a ceiling (:attr:`max_false_rate`), keeping every tracker within it
            on the photographs, leave one rig out, comes before F1), and ``figures`` and, per tracker,
            ``trackers``: the photographs' :func:`bench.evaluate.outcomes.detection_figures` under each (``loro``:
            each rig under its fold's choice, pooled). Without photographs (none in the tally), ``kept`` is the
            one choice made.
        """
        from bench.evaluate.loro import choose_by_fold

        settings = sorted({s for s, _, _, _ in self.counts})
        rigs = sorted({k for s, _, g, k in self.counts if g == "real"})
        only = pick(None, False)
        if len(rigs) < 2:
            return {"in_sample": pick(None, True), "by_rig": {}, "renders_only": only, "kept": pick(None, True),
                    "rigs": rigs, "figures": {}, "trackers": {}}
        fc = choose_by_fold({s: self.rig_counts(s) for s in settings}, lambda held: pick(held, True))

        def figures(tracker=None):
            def pooled(setting_of):
                return sum((self.rig_counts(setting_of(r), tracker).get(r, np.zeros(6, int)) for r in rigs),
                           np.zeros(6, int))
            return {"in_sample": detection_figures(pooled(lambda r: fc.in_sample)),
                    "loro": detection_figures(pooled(lambda r: fc.by_rig[r])),
                    "renders_only": detection_figures(pooled(lambda r: only))}

        figs = figures()
        trackers = sorted({t for _, t, g, _ in self.counts if g == "real"})
        per = {t: figures(t) for t in trackers}

        def rank(k):  # within the ceiling first (every tracker), then F1
            return (within_ceiling(per, k, self.max_false_rate), figs[k]["f1"])

        better = rank("loro") > rank("renders_only")
        return {"in_sample": fc.in_sample, "by_rig": fc.by_rig, "renders_only": only,
                "kept": fc.in_sample if better else only, "rigs": rigs, "figures": figs, "trackers": per}

    def records(self) -> list[dict]:
        """One dict per setting, tracker, group and kind: counts and :func:`detection_figures`."""
        return [{"stage": self.stage, "setting": s, "tracker": t, "group": g, "kind": k, **counts_record(c),
                 **detection_figures(c), "mae_px": float("nan")} for (s, t, g, k), c in self.counts.items()]

    def by_group(self, setting: str) -> dict:
        """group -> (kind -> pooled counts) of a setting, over its trackers."""
        out: dict = {}
        for (s, _, g, k), c in self.counts.items():
            if s == setting:
                kinds = out.setdefault(g, {})
                kinds[k] = kinds.get(k, 0) + c
        return out


def within_ceiling(per_tracker: dict, which: str, max_false_rate: float | None) -> bool:
    """Whether every tracker's false-report rate on the photographs under ``which`` (``in_sample``, ``loro`` or
    ``renders_only``; ``per_tracker``: tracker -> :meth:`Tally.judge`'s figures) is within ``max_false_rate``
    (always, without a ceiling; a NaN rate, no stripe-less row, is within it).

    Examples
    --------
    >>> within_ceiling({"a": {"loro": {"false_report_rate": 0.05}}}, "loro", 0.1)
    True
    >>> within_ceiling({"a": {"loro": {"false_report_rate": 0.2}}}, "loro", 0.1)
    False
    """
    return max_false_rate is None or not any(v[which]["false_report_rate"] > max_false_rate
                                             for v in per_tracker.values())


def judged_lines(judged: dict, max_false_rate: float | None = None) -> list[str]:
    """What a stage's :meth:`Tally.judge` found, in a few lines: the photographs' F1 / false-report rate under the
    choice made with all of them, leave one rig out, and under the renders' choice, and which was kept (with the
    procedure's false-report ceiling, ``max_false_rate``: whether the ceiling decided it)."""
    if not judged.get("figures"):
        return [f"  on the photographs: fewer than two rigs, not judged leave one rig out; kept {judged['kept']}"]
    f = judged["figures"]

    def fig(k):
        return f"F1 {f[k]['f1']:.3f} / false-report rate {f[k]['false_report_rate']:.3f}"

    moved = {r: c for r, c in judged["by_rig"].items() if c != judged["in_sample"]}
    folds = ("every fold chose the same" if not moved else
             f"{len(moved)} of {len(judged['by_rig'])} folds chose otherwise: "
             + "; ".join(f"without {r}: {c}" for r, c in moved.items()))
    per = judged.get("trackers", {})
    by_ceiling = (within_ceiling(per, "loro", max_false_rate) and f["loro"]["f1"] <= f["renders_only"]["f1"]
                  and not within_ceiling(per, "renders_only", max_false_rate))
    verdict = ("leave one rig out the photographs' choice keeps every tracker within the false-report ceiling and the "
               "renders' choice does not: kept the choice made with them"
               if by_ceiling and judged["kept"] == judged["in_sample"] != judged["renders_only"] else
               "the photographs improve on the renders' choice: kept the choice made with them"
               if judged["kept"] == judged["in_sample"] and judged["in_sample"] != judged["renders_only"] else
               "the renders' choice is the same" if judged["in_sample"] == judged["renders_only"] else
               "the photographs do not improve on the renders' choice leave one rig out: kept the renders' choice")
    named = "" if judged["in_sample"] == judged["kept"] else f" ({judged['in_sample']})"
    return [f"  on the photographs ({len(judged['rigs'])} rigs): in sample{named} {fig('in_sample')}; "
            f"leave one rig out {fig('loro')} ({folds})",
            f"  chosen on renders and synthetic frames alone: {judged['renders_only']}, {fig('renders_only')}; "
            f"{verdict}"]


def run_study(load_profile, run, profile, out, quiet: bool):
    """What every ``stripebench tune WHAT`` does before it prints: read the tuning profile and run.

    Parameters
    ----------
    load_profile : callable
        ``load_profile(path) -> profile``, the procedure's reader (raises :class:`bench.config.ConfigError`).
    run : callable
        ``run(profile, out, progress=bool) -> tuple``, the procedure.
    profile : path
        The tuning profile (TOML).
    out : path
        Output folder (created by ``run``).
    quiet : bool
        No progress output.

    Returns
    -------
    tuple
        ``(profile, out, result)``: the profile read, ``out`` as a path and what ``run`` returned.
    """
    profile = load_profile(profile)
    out = pathlib.Path(out)
    return profile, out, run(profile, out, progress=not quiet)


#: The columns of a procedure's CSV: one line per stage, setting, tracker, group and kind (:meth:`Tally.records`).
RECORD_FIELDS = ("stage", "setting", "tracker", "group", "kind", "n_hit", "n_wrong", "n_missed", "n_false", "n_quiet",
                 "n_unknown", "precision", "recall", "f1", "false_report_rate")


def write_records(out, name: str, records: list[dict], summary: dict, fields=RECORD_FIELDS) -> None:
    """What every ``stripebench tune WHAT`` writes into the folder ``out``: ``records`` as the CSV file
    ``name`` (the columns ``fields``; floats with 6 decimals, a missing value empty) and ``summary``
    as ``summary.json``."""
    out = pathlib.Path(out)
    with open(out / name, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(fields))
        w.writeheader()
        for r in records:
            w.writerow({k: (f"{r[k]:.6f}" if isinstance(r.get(k), float) else r.get(k, "")) for k in fields})
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
