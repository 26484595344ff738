"""``stripebench trainset``: large seeded sets of rendered frames with per-row truth, for learned trackers.

A training set is a frame set (:mod:`bench.store.frameset`, the layout of ``stripebench export``)
with one documented extension: a colour-camera frame is stored as the RGB photograph
(``images/FRAME.png``, 8-bit RGB, and ``FRAME_off.png``) and :func:`tracker_view` turns it into what
a tracker gets in a run (:func:`bench.run.camera_view.tracker_images`, the ``auto`` channel rule);
``frames.csv`` has the columns of :data:`FRAME_COLUMNS` (``camera``, ``laser_wavelength_nm``,
``unit`` added); every frame's truth is in ``truth/`` (all of it is training data; the held-out
split is by unit, :func:`holdout_of`). ``trainset.json`` holds the seed, the draw rules and every
unit's scene parameters.

Conditions: each unit is one scene drawn (seeded by ``[seed, unit]``) over the ``field``
profile's classes and the paper's materials: object, material, wall and table, textures and a
polished table, mono band-pass or colour camera without a filter, JPEG, defocus, illuminant,
lux, laser power, line width and exposure; its mirror angles are drawn uniformly over the
object's range and each angle is written with ``noise_draws`` independent sensor-noise draws
(the same Mitsuba render). Render seeds start at :data:`SEED_BASE`, so no frame is a frame of
the ``paper`` run (seed 0); :func:`plan` checks that against the paper profile's frames.

Streamed and resumable: every frame is written as it renders (its ``images/FRAME.json`` last,
the mark of a finished frame) and a rerun skips finished frames; units run in this process or
on Dask (a ``LocalCluster`` of ``workers`` processes, or a scheduler's address), as sweeps do.
"""

from __future__ import annotations

import csv
import io
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from bench.errors import InputError
from bench.store import frameset as fs
from bench.store.files import atomic_write_bytes, atomic_write_text
from bench.store.provenance import git_revision, versions

__all__ = ["FORMAT", "SEED_BASE", "FRAME_COLUMNS", "draw_unit", "plan", "paper_frames", "render_unit",
           "build_trainset", "read_trainset", "tracker_view", "holdout_of", "frame_key"]

FORMAT = 1
SEED_BASE = 10_000  #: render seeds are SEED_BASE + unit (the paper run renders with seed 0)
FRAME_COLUMNS = ("frame", "image", "background", "unit", "scene", "material", "camera", "laser_wavelength_nm",
                 "angle_deg", "seed", "noise_draw", "height", "width")
MATERIALS = ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed")
MATERIAL_WEIGHTS = (0.2, 0.12, 0.12, 0.1, 0.22, 0.12, 0.12)
OBJECTS = ("cone", "hand", "plane", "sphere")
TEXTURES = ("wood", "floor", "carpet", "checker", "charuco", "paper", "print")
ILLUMINANTS = ("D65", "A", "LED-B3", "daylight", "FL2", "D50")


def _loguniform(rng, lo, hi) -> float:
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def draw_unit(seed: int, unit: int, *, width: int = 512, height: int = 480) -> dict[str, Any]:
    """The scene parameters of one unit (``scenes.make`` keywords plus ``scene``), seeded by ``[seed, unit]``."""
    rng = np.random.default_rng([int(seed), int(unit)])
    colour = bool(rng.random() < 0.5)
    p: dict[str, Any] = {"scene": str(rng.choice(OBJECTS)), "material": str(rng.choice(MATERIALS, p=MATERIAL_WEIGHTS)),
                         "width": int(width), "height": int(height), "spp": "auto", "ambient_spp": "auto",
                         "seed": SEED_BASE + int(unit)}
    p["background"] = str(rng.choice(["none", "wall"]))
    if p["background"] == "wall":
        p["background_distance_cm"] = float(rng.uniform(45.0, 90.0))
    p["support"] = str(rng.choice(["none", "table"], p=[0.4, 0.6]))
    for key, prob in (("support_texture", 0.5 if colour else 0.2), ("background_texture", 0.4 if colour else 0.15),
                      ("object_texture", 0.3 if colour else 0.1)):
        if key == "support_texture" and p["support"] == "none":
            continue
        if key == "background_texture" and p["background"] == "none":
            continue
        if rng.random() < prob:
            p[key] = str(rng.choice(TEXTURES))
    if p["support"] == "table" and rng.random() < 0.15:
        p["support_finish"] = "polished"
    p["ambient_illuminant"] = str(rng.choice(ILLUMINANTS))
    p["ambient_lux"] = _loguniform(rng, 100.0, 3000.0) if colour else _loguniform(rng, 100.0, 1500.0)
    p["laser_power_mw"] = _loguniform(rng, 0.7, 10.0)
    p["exposure_ms"] = _loguniform(rng, 2.0, 20.0)
    p["line_fwhm_mrad"] = float(rng.uniform(1.5, 4.0))
    if colour:
        p["camera"], p["filter"] = "rgb", "none"
        if rng.random() < 0.7:
            p["jpeg_quality"] = int(rng.integers(70, 96))
        if rng.random() < 0.4:
            p["defocus_px"] = float(rng.uniform(0.2, 1.0))
    return p


def _scene(params: dict):
    import scenes

    kw = {k: v for k, v in params.items() if k != "scene"}
    return scenes.make(params["scene"], **kw)


def plan(n_units: int, angles_per_unit: int, seed: int, *, width: int = 512, height: int = 480,
         noise_draws: int = 1) -> list[dict[str, Any]]:
    """Every unit of a training set: its scene parameters and mirror angles (deg), seeded.

    A draw the scene refuses (a wall through the object) is drawn again with the next
    sub-seed. Raises :class:`bench.errors.InputError` if a planned frame is a frame of the
    ``paper`` run (:func:`paper_frames`)."""
    if n_units < 1 or angles_per_unit < 1 or noise_draws < 1:
        raise InputError("a training set needs at least one unit, one angle per unit and one noise draw")
    units = []
    for u in range(int(n_units)):
        for attempt in range(20):
            params = draw_unit(seed, u * 1000 + attempt, width=width, height=height)
            params["seed"] = SEED_BASE + u
            try:
                scene = _scene(params)
            except ValueError:
                continue
            break
        else:  # pragma: no cover - 20 refused draws
            raise InputError(f"unit {u}: no valid scene in 20 draws")
        lo, hi = (float(a) for a in scene.object.default_angles(scene.rig.zeta_deg, 2))
        rng = np.random.default_rng([int(seed), u, 7])
        angles = np.sort(rng.uniform(lo, hi, int(angles_per_unit)))
        units.append({"unit": u, "params": params, "angles_deg": [float(a) for a in angles],
                      "noise_draws": int(noise_draws)})
    paper = paper_frames()
    clash = [frame_key(u["params"], a) for u in units for a in u["angles_deg"] if frame_key(u["params"], a) in paper]
    if clash:
        raise InputError(f"the training set would render {len(clash)} frame(s) of the paper run, e.g. {clash[0]}")
    return units


def frame_key(params: dict, angle_deg: float) -> tuple:
    """What identifies a rendered frame: object, material, geometry (wall, table), angle and seed."""
    return (params["scene"], params["material"], params.get("background", "wall"),
            round(float(params.get("background_distance_cm", -1.0)), 6), params.get("support", "none"),
            round(float(angle_deg), 9), int(params.get("seed", 0)))


def paper_frames() -> set:
    """The :func:`frame_key` of every frame the ``paper`` profile renders."""
    from bench.config import profile
    from bench.run.plan import angles_for, scene_for

    cfg = profile("paper")
    keys = set()
    for exp in cfg.experiments:
        scene = scene_for(exp, cfg)
        params = {"scene": exp.scene, **scene.params}
        for a in angles_for(exp, scene):
            keys.add(frame_key(params, a))
    return keys


def holdout_of(unit: int, seed: int, fraction: float) -> bool:
    """Whether a unit is held out for validation: seeded and stable (as :func:`bench.store.frameset.split_of`).

    >>> holdout_of(3, 0, 0.0), holdout_of(3, 0, 1.0)
    (False, True)
    """
    return fs.split_of(f"unit-{int(unit)}", seed, fraction) == "test"


def _frame_id(unit: int, i: int, draw: int) -> str:
    return f"u{int(unit):04d}-{int(i):02d}-n{int(draw)}"


def _png(image: np.ndarray) -> bytes:
    import imageio.v3 as iio

    return iio.imwrite("<bytes>", np.ascontiguousarray(image), extension=".png")


def render_unit(spec: dict[str, Any], root: str) -> list[dict[str, Any]]:
    """Render one unit into the training set ``root`` (frames already written are skipped); its frame rows.
    Runs in this process or on a Dask worker."""
    root = Path(root)
    params = spec["params"]
    scene = None
    rows = []
    for i, angle in enumerate(spec["angles_deg"]):
        for draw in range(spec["noise_draws"]):
            fid = _frame_id(spec["unit"], i, draw)
            meta_path = root / "images" / f"{fid}.json"
            if meta_path.exists():
                rows.append(json.loads(meta_path.read_text()))
                continue
            if scene is None:
                scene = _scene(params)
            frame = scene.render(float(angle), spp=scene.params["spp"], seed=params["seed"], noise_draw=draw)
            rgb = getattr(frame, "rgb", None)
            on = rgb if rgb is not None else frame.image
            off = frame.rgb_background if rgb is not None else frame.background
            atomic_write_bytes(root / "images" / f"{fid}.png", _png(on))
            atomic_write_bytes(root / "images" / f"{fid}_off.png", _png(off))
            t = frame.truth
            false = t.false_columns if t.false_mask is not None else None
            atomic_write_text(root / "truth" / f"{fid}.csv", fs.truth_csv(t.columns, t.points_cm, t.part, false))
            row = {"frame": fid, "image": f"images/{fid}.png", "background": f"images/{fid}_off.png",
                   "unit": int(spec["unit"]), "scene": params["scene"], "material": params["material"],
                   "camera": scene.params["camera"], "laser_wavelength_nm": float(scene.params["laser_wavelength_nm"]),
                   "angle_deg": float(angle), "seed": int(params["seed"]), "noise_draw": int(draw),
                   "height": int(on.shape[0]), "width": int(on.shape[1])}
            atomic_write_text(meta_path, json.dumps(row))
            rows.append(row)
    return rows


def _execute(units, root, *, workers: int | None, scheduler: str | None, say) -> dict:
    if scheduler is None and not workers:
        for k, u in enumerate(units):
            render_unit(u, str(root))
            say(f"  unit {k + 1}/{len(units)} ({u['params']['scene']}, {u['params']['material']})")
        return {"engine": "sync", "workers": 0}
    import logging

    from dask.distributed import Client, LocalCluster, as_completed

    from scenes import variant as _variant

    logging.getLogger("distributed").setLevel(logging.ERROR)
    cluster = None
    if scheduler:
        client = Client(scheduler, timeout=30)
    else:
        env = {_variant.ENV_VARIANT: _variant.choose()}
        cluster = LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None, env=env, silence_logs=logging.ERROR)
        client = Client(cluster, timeout=30)
    try:
        futs = [client.submit(render_unit, u, str(root), pure=False, key=f"trainset-{u['unit']}-{time.time_ns()}")
                for u in units]
        for k, f in enumerate(as_completed(futs)):
            f.result()
            say(f"  unit {k + 1}/{len(units)} done")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return {"engine": "external" if scheduler else "local", "workers": workers}


def build_trainset(out_dir, *, n_units: int = 40, angles_per_unit: int = 4, seed: int = 1, noise_draws: int = 2,
                   width: int = 512, height: int = 480, workers: int | None = None, scheduler: str | None = None,
                   quiet: bool = False) -> Path:
    """Render (or finish rendering) a training set into ``out_dir``; returns the folder.

    Raises
    ------
    bench.errors.InputError
        ``out_dir`` holds a training set of other settings, or another kind of folder's files.
    """
    def say(m):
        if not quiet:
            print(m, file=sys.stderr, flush=True)

    root = Path(out_dir)
    # a unit's frames depend on the seed and its index only: the number of units may grow or shrink
    identity = {"kind": "stripebench-trainset", "format": FORMAT, "seed": int(seed),
                "angles_per_unit": int(angles_per_unit), "noise_draws": int(noise_draws), "width": int(width),
                "height": int(height)}
    ident_path = root / "trainset.identity.json"
    if root.exists() and any(root.iterdir()):
        if not ident_path.exists():
            raise InputError(f"{str(root)!r} holds files but no training set: choose an empty folder")
        old = json.loads(ident_path.read_text())
        if old != identity:
            raise InputError(f"{str(root)!r} holds a training set of other settings ({old}); choose another folder")
    for d in ("images", "truth"):
        (root / d).mkdir(parents=True, exist_ok=True)
    atomic_write_text(ident_path, json.dumps(identity, indent=1) + "\n")
    t0 = time.perf_counter()
    units = plan(n_units, angles_per_unit, seed, width=width, height=height, noise_draws=noise_draws)
    say(f"stripebench trainset: {len(units)} units x {angles_per_unit} angles x {noise_draws} noise draws")
    info = _execute(units, root, workers=workers, scheduler=scheduler, say=say)
    rows = []
    for u in units:
        rows += render_unit(u, str(root))  # every frame is finished now: this only reads their records
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FRAME_COLUMNS, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: r[k] for k in FRAME_COLUMNS})
    atomic_write_text(root / "frames.csv", buf.getvalue())
    doc = {**identity, "frameset_format": fs.FORMAT, "n_units": int(n_units),
           "seed_base": SEED_BASE, "frames": len(rows), "engine": info, "code_revision": git_revision(),
           "versions": versions(), "render_s": round(time.perf_counter() - t0, 1),
           "draw_rules": __doc__.split("Conditions:")[1].split("Streamed")[0].strip(),
           "images": {"mono": "PNG, 8-bit grey (the tracker's frame)",
                      "rgb": "PNG, 8-bit RGB photograph; trackers see bench.run.camera_view.tracker_images of it"},
           "units": units}
    atomic_write_bytes(root / "trainset.json", (json.dumps(doc, indent=1) + "\n").encode())
    say(f"stripebench trainset: {len(rows)} frames in {time.perf_counter() - t0:.1f} s -> {root}")
    return root


def read_trainset(path) -> tuple[dict, list[dict]]:
    """``trainset.json`` and the rows of ``frames.csv`` of a finished training set."""
    root = Path(path)
    try:
        doc = json.loads((root / "trainset.json").read_text())
        rows = list(csv.DictReader(io.StringIO((root / "frames.csv").read_text())))
    except (OSError, ValueError) as exc:
        raise InputError(f"{str(root)!r} is not a finished training set: {exc}") from None
    if doc.get("kind") != "stripebench-trainset" or doc.get("format") != FORMAT:
        raise InputError(f"{str(root)!r}: a training set of format {doc.get('format')!r}, expected {FORMAT}")
    return doc, rows


def tracker_view(root, row: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(image, background, true columns (H,)) of one frame as a tracker gets it in a run."""
    import imageio.v3 as iio

    from bench.run.camera_view import laser_colour
    from bench.evaluate.pixels import select_channel

    root = Path(root)
    on = iio.imread(root / row["image"])
    off = iio.imread(root / row["background"])
    if on.ndim == 3:
        laser = laser_colour(float(row["laser_wavelength_nm"]))
        on, off = select_channel(on, "auto", laser), select_channel(off, "auto", laser)
    return on, off, _truth_cols(root / "truth" / f"{row['frame']}.csv", int(row["height"]))


def _truth_cols(path: Path, height: int) -> np.ndarray:
    cols = np.full(height, np.nan)
    for r in csv.DictReader(io.StringIO(path.read_text())):
        if r["col"]:
            cols[int(r["row"])] = float(r["col"])
    return cols
