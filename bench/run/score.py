"""``stripebench score``: a submission's columns on an exported frame set, scored as an ordinary run.

A submission (``submission.csv``, optional ``times.csv``: :mod:`bench.store.frameset`)
is validated against the frame set first; a submission with problems is
refused with every problem in one line (:class:`SubmissionError`). Then, per
experiment of the frame set's configuration, a
:class:`bench.store.checkpoint.ScanResult` is built from the set's truth
files: the submission under its own label, beside the configuration's built-in
trackers run (through :func:`bench.run.track.track_frame`) on the exported
PNGs. From there it is a run: :func:`bench.run.experiment.scan_tables` and
:func:`bench.run.experiment.finish_run` write the same metrics, samples,
robust statistics, ratios and summary as ``stripebench run`` (the summary of
kind ``score`` also names the submission), so the report and the gate read it.
The submission is compared with the baselines as the DP trackers are.

A built-in tracker's own output, submitted, scores byte for byte what
``stripebench run`` gives that tracker on the same configuration when the frame set
is the run's frames (a set exported with ``--test-fraction 0``; a test frame is
rendered at an angle of its own, :func:`bench.run.export.test_frame`)
(``tests/bench/run/test_score.py``); only the time column comes from
``times.csv`` instead of the harness's clock.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from bench.config import ConfigError, parse, with_overrides
from bench.run.plan import say
from bench.store import frameset as fs
from bench.store.checkpoint import FALSE_K, ScanResult, write_checkpoint
from bench.store.figdata import GalleryFrame
from bench.store.files import RunFolderError, config_hash
from bench.store.provenance import code_fingerprint
from bench.store.runfolder import RunFolder, safe_dir_name

__all__ = ["score", "SubmissionError", "SPLIT_CHOICES"]

SPLIT_CHOICES = ("all", "dev", "test")


class SubmissionError(RunFolderError):
    """A submission with problems; :attr:`problems` holds one line per problem."""

    def __init__(self, problems: list[str]):
        super().__init__(f"the submission has {len(problems)} problem(s); first: {problems[0]}")
        self.problems = list(problems)


def _label(label: str | None, submission: Path, builtins) -> str:
    from bench.config import LABEL_CHARS

    label = safe_dir_name(submission.resolve().name) if label is None else label
    if not isinstance(label, str) or not label or not set(label) <= LABEL_CHARS:
        raise ConfigError(f"--label must be letters, digits, '_', '-' or '.', got {label!r}")
    if label in builtins:
        raise ConfigError(f"--label {label!r} is the label of a built-in tracker of this score; choose another")
    return label


def score(dataset, submission, out_dir, *, label: str | None = None, trackers=None, split: str = "all",
          quiet: bool = False, force: bool = False) -> Path:
    """Score ``submission`` on the frame set ``dataset`` into the run folder ``out_dir``.

    Parameters
    ----------
    dataset : path-like
        An exported frame set (``stripebench export``).
    submission : path-like
        A folder with ``submission.csv`` (and optionally ``times.csv``).
    out_dir : path-like
        The scored run's folder (kind ``score``).
    label : str, optional
        The submission's label in every table (default: the submission folder's name).
    trackers : sequence of bench.config.TrackerSpec, optional
        Built-in trackers to run on the exported frames beside it (default: the
        frame set's configuration's; its baselines and DP trackers not among
        them are dropped). An empty sequence: none, the submission is scored alone
        (no improvement ratios then).
    split : str
        ``all`` frames, or only the ``dev`` or ``test`` ones.
    quiet, force : bool
        No progress notes; clear a folder holding another run first.

    Raises
    ------
    SubmissionError
        The submission has problems (every one in :attr:`SubmissionError.problems`).
    bench.store.frameset.FrameSetError, bench.config.ConfigError, bench.store.runfolder.RunFolderError
        Not a frame set, a bad label or tracker setting, a folder that cannot be used.
    """
    from bench.run.experiment import GALLERY_FRAMES, figure_data, finish_run, scan_tables
    from bench.run.track import build_trackers, track_frame
    from bench.evaluate import tables as analysis
    from scenes.rig import Rig

    if split not in SPLIT_CHOICES:
        raise ConfigError(f"--split must be one of {', '.join(SPLIT_CHOICES)}, got {split!r}")
    t_start = time.perf_counter()
    dataset, submission = Path(dataset), Path(submission)
    fset = fs.read_frameset(dataset)
    if fset.meta.get("test_truth") == "withheld" and split != "dev":
        raise fs.FrameSetError(f"{str(dataset)!r} is a participants' bundle: its test truth is withheld, so it "
                               "scores --split dev only; the organiser scores the test split on the full frame set")
    config = parse(fset.meta["config"], "dataset.json", machine=False)
    if config_hash(config.identity()) != fset.meta["config_hash"]:
        raise fs.FrameSetError(f"{str(dataset / 'dataset.json')!r}: its `config` does not match its `config_hash` "
                               f"({config_hash(config.identity())} vs {fset.meta['config_hash']}): edited after export; "
                               "export the frame set again")
    alone = trackers is not None and len(trackers) == 0
    if alone:
        config = with_overrides(config, baselines=[], dp=[])
    elif trackers is not None:
        labels = [s.label for s in trackers]
        config = with_overrides(config, trackers=[s.to_value() for s in trackers],
                                baselines=[b for b in config.baselines if b in labels],
                                dp=[d for d in config.dp if d in labels])
    label = _label(label, submission, config.trackers)
    sub, problems = fs.read_submission(submission, fset)
    if problems:
        raise SubmissionError(problems)
    tracker_objs = {} if alone else build_trackers(config.tracker_specs)
    names = [*tracker_objs, label]
    identity = {"kind": "score", "name": config.name, "dataset": fset.meta["config_hash"],
                "dataset_revision": fset.meta.get("code_revision"), "submission": sub.checksum, "label": label,
                "split": split, "config": config.identity(), **({"alone": True} if alone else {})}
    folder = RunFolder(Path(out_dir), kind="score")
    folder.open(identity, code_fingerprint(tracker_objs.values()), force=force, say=lambda m: say(m, False))
    try:
        restore = {**config.restore_by_label(), label: config.restore}
        records, samples, scan_info, gallery, fig7 = [], [], [], [], None
        warm = set()
        for k, exp in enumerate(config.experiments):
            meta = fset.experiment(exp.key)
            frames = [f for f in fset.frames_of(exp.key) if split == "all" or f["split"] == split]
            if not frames:
                continue
            t0 = time.perf_counter()
            H, W = frames[0]["height"], frames[0]["width"]
            res = ScanResult.empty(exp.key, [f["angle_deg"] for f in frames], H, names)
            res.variant, res.width = meta["variant"], W
            if meta["false_stripes"]:
                res.false_columns = np.full((len(frames), H, FALSE_K), np.nan)
            images = []
            for i, f in enumerate(frames):
                cols, pts, on, false = fs.read_truth(fset.truth_path(f), H, FALSE_K if meta["false_stripes"] else None)
                res.truth_columns[i], res.truth_points_cm[i], res.on_object[i] = cols, pts, on
                if false is not None:
                    res.false_columns[i] = false
                image = fs.read_png(dataset / f["image"], (H, W))
                background = fs.read_png(dataset / f["background"], (H, W))
                images.append((image, background))
                for n, t in tracker_objs.items():
                    if n not in warm:  # first calls compile (numba): kept out of the per-frame times, as in a scan
                        track_frame(t, np.zeros((H, W), np.uint8), np.zeros((H, W), np.uint8))
                        warm.add(n)
                    r = track_frame(t, image, background)
                    res.columns[n][i], res.scores[n][i], res.seconds[n][i] = r.columns, r.score, r.seconds
                    res.status[n][i], res.messages[n][i] = r.status, r.message
                res.columns[label][i] = sub.columns[f["frame"]]
                res.scores[label][i] = sub.scores[f["frame"]]
                res.seconds[label][i] = sub.ms[f["frame"]] / 1e3
                res.done[i] = True
            write_checkpoint(folder.checkpoint(exp.key), res)
            try:
                rig = Rig(**meta["rig"])
            except (TypeError, ValueError) as exc:
                raise fs.FrameSetError(f"{str(dataset / 'dataset.json')!r}: experiment {exp.key!r} has no valid `rig` "
                                       f"({exc})") from None
            recs, samps = scan_tables(config, k, exp, rig, res, restore=restore)
            records += recs
            samples += samps
            for i in analysis.worst_frames(res, GALLERY_FRAMES):
                cols = {n: res.columns[n][i] for n in res.columns}
                gallery.append(GalleryFrame(exp.key, int(i), images[i][0], res.truth_columns[i], cols))
                if fig7 is None:
                    fig7 = figure_data(exp.key, float(res.angles[i]), images[i][0], images[i][1],
                                       res.truth_columns[i], cols)
            failures = {n: int(np.count_nonzero(res.status[n])) for n in res.status}
            scan_info.append({"experiment": exp.key, "frames": len(frames),
                              "angles_deg": [float(f["angle_deg"]) for f in frames], "wall_s": time.perf_counter() - t0,
                              "render_s": 0.0, "variant": res.variant, "failures": failures, "rig": dict(meta["rig"]),
                              "failure_messages": {n: sorted({m for m in res.messages[n] if m})[:5]
                                                   for n in res.messages}})
            say(f"[{k + 1}/{len(config.experiments)}] {exp.key}: {len(frames)} frames scored", quiet)
        if not scan_info:
            raise ConfigError(f"--split {split}: the frame set has no {split} frames")
        extra = {"submission": {"label": label, "path": str(submission), "checksum": sub.checksum,
                                "dataset": str(dataset), "dataset_config_hash": fset.meta["config_hash"],
                                "dataset_revision": fset.meta.get("code_revision"), "split": split,
                                "frames": sum(s["frames"] for s in scan_info),
                                "timed": bool(any(np.isfinite(v) for v in sub.ms.values())),
                                **({"alone": True} if alone else {})}}
        return finish_run(config, folder.path, records, samples, scan_info, gallery, fig7, t_start=t_start,
                          quiet=quiet, render_ahead={"off": "scored from an exported frame set (no rendering)"},
                          kind="score", submissions=(label,), builtins=() if alone else None, extra=extra)
    finally:
        folder.unlock()
