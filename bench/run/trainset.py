"""``stripebench trainset``: large seeded sets of rendered frames with per-row truth, for learned trackers.

A training set is a frame set (:mod:`bench.store.frameset`, the layout of ``stripebench export``)
with one documented extension: a colour-camera frame is stored as the RGB photograph
(``images/FRAME.png``, 8-bit RGB, and ``FRAME_off.png``) and :func:`tracker_view` turns it into what
a tracker gets in a run (:func:`bench.run.camera_view.tracker_images`, the ``auto`` channel rule);
``frames.csv`` has the columns of :data:`FRAME_COLUMNS` (``camera``, ``laser_wavelength_nm``,
``unit`` added); every frame's truth is in ``truth/`` (all of it is training data; the held-out
split is by unit, :func:`holdout_of`). ``trainset.json`` holds the seed, the draw rules and every
unit's scene parameters.

Conditions (:data:`DRAW_RULES`, chosen by ``draws``): each unit is one scene drawn (seeded by
``[seed, unit]``) over the ``field`` profile's classes and the paper's materials: object,
material, wall and table, textures and a polished table, mono band-pass or colour camera without
a filter, illuminant and line width; its mirror angles are drawn uniformly over the object's range
and each angle is written with ``noise_draws`` independent sensor-noise draws (the same Mitsuba
render). Rules 1 (the first weights') draw lux, laser power, exposure, JPEG and defocus once per
unit; rules 2 (the default) widen the lines and draw those five once per frame (angle and noise
draw: free, they apply after the render cache), with saturated, blooming stripes in a third of the
frames. Render seeds start at :data:`SEED_BASE`, so no frame is a frame of the ``paper`` run (seed
0); :func:`plan` checks that against the paper profile's frames.

Rules 3 add, per unit with probability 0.5, a distractor (``scenes.distractors``: a stripe cut from the
top or the bottom rows and a lit door edge, a lamp, LEDs, a window, a lit sphere or a drawn frame in
those rows), so a network learns to stay quiet where photographs of real rigs have no stripe; the
distractor applies after the render cache, so it costs no render.

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
from bench.evaluate.pixels import CHANNELS
from bench.store import frameset as fs
from bench.store.files import atomic_write_bytes, atomic_write_text
from bench.store.provenance import git_revision, versions

__all__ = ["FORMAT", "SEED_BASE", "FRAME_COLUMNS", "DRAW_RULES", "PHOTOMETRY_KEYS", "draw_unit", "draw_photometry",
           "plan", "paper_frames", "render_unit",
           "build_trainset", "read_trainset", "VIEWS", "tracker_view", "holdout_of", "frame_key"]

FORMAT = 1
SEED_BASE = 10_000  #: render seeds are SEED_BASE + unit (the paper run renders with seed 0)
FRAME_COLUMNS = ("frame", "image", "background", "unit", "scene", "material", "camera", "laser_wavelength_nm",
                 "angle_deg", "seed", "noise_draw", "height", "width")
MATERIALS = ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed")
MATERIAL_WEIGHTS = (0.2, 0.12, 0.12, 0.1, 0.22, 0.12, 0.12)
OBJECTS = ("cone", "hand", "plane", "sphere")
TEXTURES = ("wood", "floor", "carpet", "checker", "charuco", "paper", "print")
ILLUMINANTS = ("D65", "A", "LED-B3", "daylight", "FL2", "D50")
#: The draw rules, by number (``stripebench trainset --draws``); a training set records its rules' text.
DRAW_RULES = {
    1: "Per unit ([seed, unit]): colour camera without a filter or mono band-pass camera, 1:1; object uniform "
       "over cone, hand, plane, sphere; material over the paper's seven (matte 0.2, absorbing 0.12, glossy 0.12, "
       "specular 0.1, patchy 0.22, polished 0.12, glazed 0.12); wall (45-90 cm) or none, 1:1; table 0.6 or "
       "none; textures on the table / wall / object with 0.5 / 0.4 / 0.3 (colour) or 0.2 / 0.15 / 0.1 (mono) "
       "over wood, floor, carpet, checker, charuco, paper, print; a polished table 0.15; illuminant uniform over "
       "D65, A, LED-B3, daylight, FL2, D50; lux log-uniform 100-3000 (colour) or 100-1500 (mono); laser power "
       "log-uniform 0.7-10 mW; exposure log-uniform 2-20 ms; line FWHM uniform 1.5-4 mrad; colour: JPEG 0.7 "
       "(quality 70-95), defocus 0.4 (0.2-1 px).",
    2: "Per unit ([seed, unit]) as rules 1 except the line FWHM: uniform 1.5-4 mrad (0.75) or 4-9 mrad (0.25, "
       "wide lines). Per frame ([seed, unit, 11, angle, noise draw]; lux, power, exposure, JPEG and defocus "
       "apply after the render cache, so they cost no render): a saturated stripe (0.35: laser power "
       "log-uniform 5-20 mW, exposure 10-40 ms; the stripe clips and blooms) or rules 1's power and exposure; "
       "lux log-uniform 100-5000 (colour) or 100-1500 (mono); colour: JPEG 0.7 (quality 60-95), defocus 0.5 "
       "(0.2-2.5 px); mono: defocus 0.2 (0.2-1.5 px).",
    3: "As rules 2, and per unit, drawn after rules 2's draws: a distractor (scenes.distractors) with "
       "probability 0.5, uniform over short, door_edge, lamp, leds, window, sphere, overlay (the stripe cut "
       "from the top or the bottom rows, the distractor in those rows; placed from the unit's render seed).",
}
DEFAULT_DRAWS = 2
PHOTOMETRY_KEYS = ("ambient_lux", "laser_power_mw", "exposure_ms", "jpeg_quality", "defocus_px")


def _loguniform(rng, lo, hi) -> float:
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def draw_unit(seed: int, unit: int, *, width: int = 512, height: int = 480,
              draws: int = DEFAULT_DRAWS) -> dict[str, Any]:
    """The scene parameters of one unit (``scenes.make`` keywords plus ``scene``), seeded by ``[seed, unit]``,
    by the rules ``draws`` (:data:`DRAW_RULES`; rules 2's per-frame parameters: :func:`draw_photometry`)."""
    if draws not in DRAW_RULES:
        raise InputError(f"draw rules must be one of {sorted(DRAW_RULES)}, got {draws!r}")
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
    if draws >= 2 and rng.random() < 0.25:  # rules 2: wide lines (drawn after rules 1's draws: those stay)
        p["line_fwhm_mrad"] = float(rng.uniform(4.0, 9.0))
    if colour:
        p["camera"], p["filter"] = "rgb", "none"
        if rng.random() < 0.7:
            p["jpeg_quality"] = int(rng.integers(70, 96))
        if rng.random() < 0.4:
            p["defocus_px"] = float(rng.uniform(0.2, 1.0))
    if draws == 3 and rng.random() < 0.5:  # rules 3: a distractor (drawn after rules 2's draws: those stay)
        from scenes import DISTRACTORS

        p["distractor"] = str(rng.choice(DISTRACTORS[1:]))
    if draws >= 2:  # drawn per frame instead (draw_photometry)
        for k in PHOTOMETRY_KEYS:
            p.pop(k, None)
    return p


def draw_photometry(seed: int, unit: int, angle_index: int, draw: int, params: dict) -> dict[str, Any]:
    """Rules 2's per-frame parameters (:data:`PHOTOMETRY_KEYS`) of one angle and noise draw of a unit whose
    scene parameters are ``params``, seeded by ``[seed, unit, 11, angle_index, draw]``. They apply after the
    render cache (laser power, ambient level, the sensor, the camera's JPEG and defocus), so every draw
    of an angle reuses its Mitsuba render.

    >>> p = draw_photometry(1, 0, 0, 0, {"camera": "rgb"})
    >>> sorted(p) == sorted(PHOTOMETRY_KEYS) and p == draw_photometry(1, 0, 0, 0, {"camera": "rgb"})
    True
    """
    rng = np.random.default_rng([int(seed), int(unit), 11, int(angle_index), int(draw)])
    colour = params.get("camera") == "rgb"
    if rng.random() < 0.35:  # a saturated stripe: it clips and blooms, as in many webcam photographs
        power, exposure = _loguniform(rng, 5.0, 20.0), _loguniform(rng, 10.0, 40.0)
    else:
        power, exposure = _loguniform(rng, 0.7, 10.0), _loguniform(rng, 2.0, 20.0)
    lux = _loguniform(rng, 100.0, 5000.0) if colour else _loguniform(rng, 100.0, 1500.0)
    jpeg = int(rng.integers(60, 96)) if colour and rng.random() < 0.7 else None
    if rng.random() < (0.5 if colour else 0.2):
        defocus = float(rng.uniform(0.2, 2.5 if colour else 1.5))
    else:
        defocus = 0.0
    return {"ambient_lux": lux, "laser_power_mw": power, "exposure_ms": exposure, "jpeg_quality": jpeg,
            "defocus_px": defocus}


def _scene(params: dict):
    import scenes

    kw = {k: v for k, v in params.items() if k != "scene"}
    return scenes.make(params["scene"], **kw)


def plan(n_units: int, angles_per_unit: int, seed: int, *, width: int = 512, height: int = 480,
         noise_draws: int = 1, draws: int = DEFAULT_DRAWS) -> list[dict[str, Any]]:
    """Every unit of a training set: its scene parameters and mirror angles (deg), seeded, by the
    rules ``draws`` (:data:`DRAW_RULES`); under rules 2 also ``photometry``, per angle and noise
    draw the parameters of :func:`draw_photometry`.

    A draw the scene refuses (a wall through the object) is drawn again with the next
    sub-seed. Raises :class:`bench.errors.InputError` if a planned frame is a frame of the
    ``paper`` run (:func:`paper_frames`)."""
    if n_units < 1 or angles_per_unit < 1 or noise_draws < 1:
        raise InputError("a training set needs at least one unit, one angle per unit and one noise draw")
    units = []
    for u in range(int(n_units)):
        for attempt in range(20):
            params = draw_unit(seed, u * 1000 + attempt, width=width, height=height, draws=draws)
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
        spec = {"unit": u, "params": params, "angles_deg": [float(a) for a in angles], "noise_draws": int(noise_draws)}
        if draws >= 2:
            spec["photometry"] = [[draw_photometry(seed, u, i, n, params) for n in range(int(noise_draws))]
                                  for i in range(len(angles))]
        units.append(spec)
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
                row = _frame_record(meta_path)
                if row is not None:
                    rows.append(row)
                    continue
            if "photometry" in spec:  # rules 2: this frame's own level, sensor and camera; the same render
                scene = _scene({**params, **spec["photometry"][i][draw]})
            elif scene is None:
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
            if "photometry" in spec:
                row["photometry"] = spec["photometry"][i][draw]
            atomic_write_text(meta_path, json.dumps(row))
            rows.append(row)
    return rows


def _frame_record(path: Path) -> dict | None:
    """A finished frame's record (``images/FRAME.json``), or None when it is damaged (not a JSON object with
    :data:`FRAME_COLUMNS`): then one line says so and the frame is rendered again."""
    from bench.store.textfiles import read_json

    try:
        row = read_json(path, "frame record")
        if not isinstance(row, dict) or any(k not in row for k in FRAME_COLUMNS):
            raise InputError(f"frame record {str(path)!r} is not a record of {', '.join(FRAME_COLUMNS)}")
    except InputError as exc:
        print(f"stripebench trainset: {exc}: rendering that frame again", file=sys.stderr, flush=True)
        return None
    return row


def _execute(units, root, *, workers: int | None, scheduler: str | None, say) -> dict:
    if scheduler is None and not workers:
        for k, u in enumerate(units):
            render_unit(u, str(root))
            say(f"  unit {k + 1}/{len(units)} ({u['params']['scene']}, {u['params']['material']})")
        return {"engine": "sync", "workers": 0}
    import logging

    from dask.distributed import Client, as_completed

    from bench.run.cluster import local_cluster

    from scenes import variant as _variant

    logging.getLogger("distributed").setLevel(logging.ERROR)
    cluster = None
    if scheduler:
        client = Client(scheduler, timeout=30)
    else:
        env = {_variant.ENV_VARIANT: _variant.choose()}
        cluster = local_cluster(int(workers), env)
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
                   quiet: bool = False, draws: int = DEFAULT_DRAWS) -> Path:
    """Render (or finish rendering) a training set into ``out_dir`` by the draw rules ``draws``
    (:data:`DRAW_RULES`); returns the folder.

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
    if draws != 1:  # (rules 1's folders, written before the rules had numbers, carry no such key)
        identity["draws"] = int(draws)
    ident_path = root / "trainset.identity.json"
    if root.exists() and any(root.iterdir()):
        if not ident_path.exists():
            raise InputError(f"{str(root)!r} holds files but no training set: choose an empty folder")
        from bench.store.textfiles import read_json

        try:
            old = read_json(ident_path, "training-set identity")
        except InputError as exc:  # the record of which settings made the frames there: never guessed
            raise InputError(f"{exc}; it says which settings made the frames in {str(root)!r}: restore it, or "
                             "choose another folder") from None
        if old != identity:
            from bench.errors import quoted

            raise InputError(f"{str(root)!r} holds a training set of other settings (its trainset.identity.json "
                             f"says {quoted(old, 400)}); choose another folder")
    for d in ("images", "truth"):
        (root / d).mkdir(parents=True, exist_ok=True)
    atomic_write_text(ident_path, json.dumps(identity, indent=1) + "\n")
    t0 = time.perf_counter()
    units = plan(n_units, angles_per_unit, seed, width=width, height=height, noise_draws=noise_draws, draws=draws)
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
           "draws": int(draws), "draw_rules": DRAW_RULES[int(draws)],
           "images": {"mono": "PNG, 8-bit grey (the tracker's frame)",
                      "rgb": "PNG, 8-bit RGB photograph; trackers see bench.run.camera_view.tracker_images of it"},
           "units": units}
    atomic_write_bytes(root / "trainset.json", (json.dumps(doc, indent=1) + "\n").encode())
    say(f"stripebench trainset: {len(rows)} frames in {time.perf_counter() - t0:.1f} s -> {root}")
    return root


def read_trainset(path) -> tuple[dict, list[dict]]:
    """``trainset.json`` and the rows of ``frames.csv`` of a finished training set."""
    from bench.store.textfiles import loads_csv, read_json, read_text

    root = Path(path)
    if not (root / "trainset.json").exists():
        raise InputError(f"{str(root)!r} is not a finished training set: no trainset.json")
    try:
        doc = read_json(root / "trainset.json", "training set")
        header, rows = loads_csv(read_text(root / "frames.csv", "frame list"), str(root / "frames.csv"))
    except InputError as exc:
        raise InputError(f"{str(root)!r} is not a finished training set: {exc}") from None
    if not isinstance(doc, dict) or doc.get("kind") != "stripebench-trainset" or doc.get("format") != FORMAT:
        got = doc.get("format") if isinstance(doc, dict) else type(doc).__name__
        raise InputError(f"{str(root)!r}: trainset.json is not a training set of format {FORMAT} (got {got!r})")
    missing = [c for c in FRAME_COLUMNS if c not in header]
    if missing:
        raise InputError(f"{str(root / 'frames.csv')!r}: no column {missing[0]!r} (a training set's frame list has "
                         f"{', '.join(FRAME_COLUMNS)})")
    for n, r in enumerate(rows, start=2):
        try:
            int(r["unit"]), int(r["height"]), int(r["width"]), float(r["laser_wavelength_nm"])
            if not 1 <= int(r["height"]) <= fs.MAX_SIDE:
                raise ValueError
        except (TypeError, ValueError):
            raise InputError(f"{str(root / 'frames.csv')!r} line {n}: unit, height, width or laser_wavelength_nm "
                             "is not a number in range") from None
        for col in ("image", "background"):
            rel = Path(r[col] or "")
            if rel.is_absolute() or ".." in rel.parts or not r[col]:
                raise InputError(f"{str(root / 'frames.csv')!r} line {n}: {col} {r[col][:80]!r} must be a path "
                                 "inside the training set")
    return doc, rows


#: The views of a frame :func:`tracker_view` gives: :data:`bench.evaluate.pixels.CHANNELS` and ``"laser"``.
VIEWS = ("auto", "laser") + tuple(c for c in CHANNELS if c != "auto")


def tracker_view(root, row: dict, channel: str = "auto", *,
                 downscale: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(image, background, true columns (H,)) of one frame as a tracker gets it in a run (``channel``
    ``"auto"``), or through another channel of a colour frame (:func:`bench.evaluate.pixels.select_channel`'s
    names, or ``"laser"``: the laser's own plain channel, as a real set's ``channel`` column may ask);
    a mono frame is the same in every view. With ``downscale`` N > 1 the stored 8-bit frames are first
    shrunk by N (:func:`bench.evaluate.pixels.downscale`, as a camera app shrinks a phone's frame: a
    narrower stripe, less noise) and the truth with them (:func:`bench.evaluate.pixels.downscale_columns`)."""
    import imageio.v3 as iio

    from bench.evaluate.pixels import downscale as shrink
    from bench.evaluate.pixels import downscale_columns, select_channel
    from bench.run.camera_view import laser_colour

    root = Path(root)
    n = int(downscale)
    on = shrink(_read_png(iio, root / row["image"]), n)
    off = shrink(_read_png(iio, root / row["background"]), n)
    if on.ndim == 3:
        laser = laser_colour(float(row["laser_wavelength_nm"]))
        ch = laser[0] if channel == "laser" else channel
        on, off = select_channel(on, ch, laser), select_channel(off, ch, laser)
    truth = _truth_cols(root / "truth" / f"{row['frame']}.csv", int(row["height"]))
    return on, off, (truth if n == 1 else downscale_columns(truth, n))


def _read_png(iio, path: Path) -> np.ndarray:
    """A training set's stored frame (one line naming the file if it is missing or damaged)."""
    if not path.is_file():
        raise InputError(f"training-set frame {str(path)!r} is missing or not a file")
    try:
        return iio.imread(path)
    except Exception as exc:  # noqa: BLE001 - whatever the decoder raises on a damaged file
        raise InputError(f"training-set frame {str(path)!r} is unreadable ({type(exc).__name__})") from None


def _truth_cols(path: Path, height: int) -> np.ndarray:
    from bench.store.textfiles import read_text

    cols = np.full(height, np.nan)
    for n, r in enumerate(csv.DictReader(io.StringIO(read_text(path, "truth"))), start=2):
        try:
            v = int(r["row"])
            if not 0 <= v < height:
                raise ValueError
            if r["col"]:
                cols[v] = float(r["col"])
        except (KeyError, TypeError, ValueError):
            raise InputError(f"truth {str(path)!r} line {n} is malformed") from None
    return cols
