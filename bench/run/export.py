"""``stripebench export``: a configuration's frames as a versioned frame set any program can track.

Every experiment of the configuration is rendered exactly as :func:`bench.run.scan.run_scan`
renders it (the same scene, angles, ``spp`` and seed, so the render cache is
shared with runs), and each frame is written as the 8-bit PNGs a tracker gets
in a run (``frame.image`` and ``frame.background`` are uint8 arrays: the PNGs
hold them losslessly) with its per-row truth. The files and their readers are
:mod:`bench.store.frameset`. The folder is a run folder of kind ``export``
(locked while written, refused if it holds another run unless ``force``).

Two parties (as BOP and Middlebury run their benchmarks): the organiser exports the
frame set and keeps it; :func:`participants_bundle` copies it without the test
split's truth (``truth_test/``) for the participants, who track every frame and send
back a submission; the organiser scores it on the full set (``stripebench score``).
A bundle scores its ``dev`` split only.

The test split cannot be rendered again from what the bundle holds: each test frame is
rendered at its nominal mirror angle moved by a uniform draw within ±:data:`TEST_JITTER` of
the experiment's angle spacing, with its own render seed, both drawn from a *test seed*
(:func:`test_frame`). The test seed is drawn with :mod:`secrets` at export and kept only
beside the withheld truth (``truth_test/withheld.json``); the bundle's ``frames.csv`` and
``dataset.json`` leave the test frames' angles out. The dev frames are the run's frames
(the configuration's angles and seed). ``export --test-seed N`` (``N`` from
``withheld.json``) writes the organiser's set again byte for byte.
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

import numpy as np

from bench.config import Config
from bench.run.plan import angles_for, renderer_for, say, scene_for
from bench.errors import InputError
from bench.run.camera_view import tracker_images
from bench.store import frameset as fs
from bench.store.files import atomic_write_bytes, atomic_write_text, config_hash
from bench.store.provenance import code_fingerprint, git_revision, versions
from bench.store.runfolder import RunFolder

__all__ = ["export", "participants_bundle", "check_bundle_folder", "test_frame", "TEST_FRACTION", "TEST_JITTER",
           "TEST_SEED_BITS", "WITHHELD"]

TEST_FRACTION = 0.3  # share of frames held out as `test` (their truth in truth_test/)
#: A test frame's angle moves by a uniform draw within ± this fraction of its experiment's angle spacing.
TEST_JITTER = 0.25
#: The test seed is an integer in [0, 2**TEST_SEED_BITS).
TEST_SEED_BITS = 63
#: The file beside the withheld truth that keeps the test seed (in ``truth_test/``; never in a bundle).
WITHHELD = "withheld.json"
UNITS = {"angle_deg": "deg (mirror angle theta)", "row": "px (image row, 0 at the top)",
         "col": "px (continuous column, pixel centre at integer values)",
         "x_cm, y_cm, z_cm": "cm (world point of the true stripe)", "rig": "cm, mm and deg as the field names say",
         "ms": "milliseconds per frame (times.csv)"}


def test_frame(angles_deg, index: int, test_seed: int, experiment_index: int) -> tuple[float, int]:
    """The mirror angle (deg) and render seed of test frame ``index`` of an experiment whose nominal angles are
    ``angles_deg``: the nominal angle moved by a uniform draw within ±:data:`TEST_JITTER` of the smallest spacing
    of the angles (1 deg for a single angle), and a seed in [0, 2**31), both from
    ``numpy.random.default_rng(SeedSequence([test_seed, experiment_index, index]))``.

    Examples
    --------
    >>> a, s = test_frame([10.0, 12.0, 14.0], 1, 5, 0)
    >>> 11.5 <= a <= 12.5 and a != 12.0, test_frame([10.0, 12.0, 14.0], 1, 5, 0) == (a, s)
    (True, True)
    """
    angles = np.asarray(angles_deg, float)
    gaps = np.diff(np.sort(angles))
    gaps = gaps[gaps > 0]
    spacing = float(gaps.min()) if gaps.size else 1.0
    rng = np.random.default_rng(np.random.SeedSequence([int(test_seed), int(experiment_index), int(index)]))
    angle = float(angles[index] + rng.uniform(-TEST_JITTER, TEST_JITTER) * spacing)
    return angle, int(rng.integers(0, 2**31))


def _test_seed(test_seed) -> int:
    import secrets

    if test_seed is None:
        return secrets.randbits(TEST_SEED_BITS)
    if isinstance(test_seed, bool) or not isinstance(test_seed, (int, np.integer)) \
            or not 0 <= test_seed < 2**TEST_SEED_BITS:
        raise InputError(f"--test-seed must be an integer in [0, 2**{TEST_SEED_BITS}), got {test_seed!r:.40}")
    return int(test_seed)


def export(config: Config, out_dir, *, test_fraction: float = TEST_FRACTION, test_seed: int | None = None,
           quiet: bool = False, force: bool = False) -> Path:
    """Render ``config``'s frames into the frame set ``out_dir``; returns the folder.

    Parameters
    ----------
    config : Config
        Its experiments, render settings and seed decide the frames; its
        trackers are kept in ``dataset.json`` (``stripebench score`` runs them beside a submission).
    out_dir : path-like
    test_fraction : float
        Share of frames in the ``test`` split (:func:`bench.store.frameset.split_of`, seeded by ``config.seed``).
    test_seed : int, optional
        The seed of the test frames' angles and renders (:func:`test_frame`); default a fresh one from
        :mod:`secrets`. It is written to ``truth_test/withheld.json`` only; the same ``test_seed`` writes the
        same set, byte for byte.
    quiet : bool
        No progress notes on stderr.
    force : bool
        Clear a folder holding another run or files first.

    Raises
    ------
    ValueError
        ``test_fraction`` outside [0, 1].
    bench.errors.InputError
        ``test_seed`` is not an integer in [0, 2**63), or an experiment has a colour camera.
    bench.store.runfolder.RunFolderError
        The folder is locked, holds another run (without ``force``) or cannot be written.
    """

    fs.split_of("x", 0, test_fraction)  # validates test_fraction
    test_seed = _test_seed(test_seed)
    for exp in config.experiments:  # before anything renders or is written
        camera = scene_for(exp, config).params.get("camera", "mono")
        if camera != "mono":
            raise InputError(f"experiment {exp.key!r} has a colour camera (camera = {camera!r}): its trackers see "
                             "a float frame through the channel rule, and a frame set holds 8-bit frames only")
    renderer_for(config)
    t0 = time.perf_counter()
    identity = {"export": config.identity(), "test_fraction": float(test_fraction), "format": fs.FORMAT}
    folder = RunFolder(Path(out_dir), kind="export")
    folder.open(identity, code_fingerprint(), force=force, say=lambda m: say(m, False))
    try:
        root = folder.path
        for d in ("images", *fs.TRUTH_DIRS.values()):
            (root / d).mkdir(exist_ok=True)
        rows, experiments = [], []
        for k, exp in enumerate(config.experiments):
            scene = scene_for(exp, config)
            angles = angles_for(exp, scene)
            spp = scene.params["spp"]
            say(f"[{k + 1}/{len(config.experiments)}] {exp.key}: {len(angles)} frames at "
                 f"{scene.rig.width}x{scene.rig.height}", quiet)
            variant, false_stripes, shown = "", False, []
            for i, nominal in enumerate(angles):
                fid = fs.frame_id(exp.key, i)
                split = fs.split_of(fid, config.seed, test_fraction)
                angle, seed = (float(nominal), config.seed) if split == "dev" else \
                    test_frame(angles, i, test_seed, k)  # the test split: where the bundle cannot say
                frame = scene.render(angle, spp=spp, seed=seed)
                shown.append(angle)
                seen, seen_off = tracker_images(frame, scene.params)  # what a tracker gets in a run
                if seen.dtype != np.uint8:
                    raise InputError(f"experiment {exp.key!r}: its trackers see a {seen.dtype} frame (a colour "
                                      "camera through a float channel rule); a frame set holds 8-bit frames only")
                H, W = seen.shape
                image, off = f"images/{fid}.png", f"images/{fid}_off.png"
                atomic_write_bytes(root / image, fs.png_bytes(seen))
                atomic_write_bytes(root / off, fs.png_bytes(seen_off))
                t = frame.truth
                false = t.false_columns if t.false_mask is not None else None
                false_stripes |= false is not None
                atomic_write_text(root / fs.TRUTH_DIRS[split] / f"{fid}.csv",
                                  fs.truth_csv(t.columns, t.points_cm, t.part, false))
                variant = frame.variant
                rows.append({"frame": fid, "image": image, "background": off, "experiment": exp.key,
                             "condition": exp.condition or exp.key, "split": split, "angle_deg": float(angle),
                             "height": H, "width": W})
            experiments.append({"key": exp.key, "index": k, "scene": exp.scene, "material": exp.material,
                                "condition": exp.condition or exp.key, "frames": int(len(angles)),
                                "angles_deg": shown, "spp": spp if spp == "auto" else int(spp), "variant": variant,
                                "false_stripes": bool(false_stripes), "rig": dataclasses.asdict(scene.rig)})
        fs.write_frames_csv(root / "frames.csv", rows)
        n_test = sum(r["split"] == "test" for r in rows)
        atomic_write_text(root / fs.TRUTH_DIRS["test"] / WITHHELD, json.dumps(
            {"test_seed": test_seed, "why": "the test frames' angles and render seeds (bench.run.export.test_frame); "
             "keep it with the withheld truth: `stripebench export --test-seed` with it writes this set again"},
            indent=1) + "\n")
        doc = {
            "format": fs.FORMAT, "kind": "stripebench-frames", "profile": config.name,
            "config_source": config.source, "config_hash": config_hash(config.identity()),
            "code_revision": git_revision(), "versions": versions(), "seed": config.seed,
            "split": {"rule": "test when the first 8 bytes of sha256('<seed>:<frame>') / 2**64 < test_fraction",
                      "test_fraction": float(test_fraction), "seed": config.seed, "dev": len(rows) - n_test,
                      "test": n_test, "truth_dirs": fs.TRUTH_DIRS,
                      "test_frames": f"rendered at the nominal angle moved by a uniform draw within ±{TEST_JITTER} of "
                                     "the angle spacing, with their own render seed, both from a test seed that "
                                     f"only {fs.TRUTH_DIRS['test']}/{WITHHELD} keeps"},
            "images": {"format": "PNG, 8-bit grey", "dtype": "uint8",
                       "what": "the laser-on (image) and laser-off (background) arrays a tracker gets in a run, "
                               "losslessly"},
            "units": UNITS, "truth_columns": list(fs.TRUTH_COLUMNS), "frame_columns": list(fs.FRAME_COLUMNS),
            "submission": {"file": "submission.csv", "columns": "frame,row,col[,score]",
                           "times": "times.csv: frame,ms (optional)"},
            "experiments": experiments, "config": config.to_dict(),
        }
        fs.write_dataset_json(root / "dataset.json", doc)
        say(f"stripebench: {len(rows)} frames ({len(rows) - n_test} dev, {n_test} test) in "
             f"{time.perf_counter() - t0:.1f} s", quiet)
        return root
    finally:
        folder.unlock()


def check_bundle_folder(frameset_dir, bundle_dir) -> None:
    """Refuse a participants' bundle folder that is the frame set's, inside it (the frame set would then
    hold a copy of itself) or holds it (the bundle would hand out the test truth, and ``--force`` on the
    bundle would delete the frame set).

    Raises
    ------
    bench.store.frameset.FrameSetError
        One line naming both folders.
    """
    a, b = Path(bundle_dir).resolve(), Path(frameset_dir).resolve()
    if a == b or b in a.parents or a in b.parents:
        raise fs.FrameSetError(f"the participants' bundle {str(bundle_dir)!r} must be a folder apart from the frame "
                               f"set {str(frameset_dir)!r} (not it, not inside it, not holding it)")


def participants_bundle(frameset, out_dir, *, force: bool = False) -> Path:
    """Copy the frame set ``frameset`` to ``out_dir`` without its test truth: the bundle a
    benchmark's organiser hands out while keeping the test split's truth for scoring.

    The bundle holds ``dataset.json`` (with ``"test_truth": "withheld"``), ``frames.csv``,
    ``images/`` and ``truth/`` (the dev split); ``stripebench score`` on it scores
    ``--split dev`` only. The test frames' angles are left out of ``frames.csv`` (empty) and of
    ``dataset.json`` (null), and the test seed stays in the frame set's ``truth_test/``.

    Raises
    ------
    bench.store.frameset.FrameSetError
        ``frameset`` is not a frame set (or is a bundle itself).
    bench.store.runfolder.RunFolderError
        ``out_dir`` holds another run or files (without ``force``), or is ``frameset`` itself.
    """
    import shutil

    src = fs.read_frameset(frameset)
    if src.meta.get("test_truth") == "withheld":
        raise fs.FrameSetError(f"{str(frameset)!r} is a participants' bundle already (its test truth is withheld)")
    out = Path(out_dir)
    check_bundle_folder(src.root, out)
    folder = RunFolder(out, kind="bundle")
    folder.open({"bundle_of": src.meta["config_hash"], "format": fs.FORMAT}, code_fingerprint(), force=force,
                say=lambda m: say(m, False))
    try:
        root = folder.path
        for sub in ("images", fs.TRUTH_DIRS["dev"]):
            if (root / sub).exists():
                shutil.rmtree(root / sub)
            shutil.copytree(src.root / sub, root / sub)
        test = {f["frame"] for f in src.frames if f["split"] == "test"}
        fs.write_frames_csv(root / "frames.csv", [{**f, "angle_deg": float("nan")} if f["frame"] in test else f
                                                  for f in src.frames])
        experiments = []
        for e in src.meta["experiments"]:  # the test frames' angles: not the participants' to know
            own = [f["frame"] for f in src.frames_of(e["key"])]
            angles = e.get("angles_deg")
            if isinstance(angles, list) and len(angles) == len(own):
                e = {**e, "angles_deg": [None if fid in test else a for fid, a in zip(own, angles)]}
            experiments.append(e)
        fs.write_dataset_json(root / "dataset.json", {**src.meta, "experiments": experiments,
                                                      "test_truth": "withheld"})
    finally:
        folder.unlock()
    return root
