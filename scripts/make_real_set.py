"""Build the shipped real set ``bench/data/real`` (images, references, check overlays).

Two steps, both repeatable:

``python scripts/make_real_set.py images SRC_DIR [NAME ...]``
    Downscale the original photographs (fetched from their public repositories,
    see ``bench/data/real/manifest.csv`` for repository, commit and path) into
    ``NAME.png`` files by block averaging. ``SRC_DIR`` holds the original files
    under the names of ``SOURCES`` below. Nothing of the source repositories but
    these pixels is used. A source with a line drawn over its stripe
    (``DRAWN_LINE``) has the line's darkening undone.

``python scripts/make_real_set.py guides NAME ... [--skip-cols N]``
    Print guide segments read off a photograph's laser-on minus laser-off
    difference (:func:`difference_guide`), as ``guides.toml`` holds them (the
    ``fh_*`` frames' guides were written so, with ``--skip-cols 70``).

``python scripts/make_real_set.py refs``
    Write ``NAME_ref.csv`` (``row,col,state``) for every image from
    ``bench/data/real/guides.toml`` and a check overlay ``docs/real/NAME_ref.png``
    (reference in green on the dimmed photograph; a bar at the left edge gives each
    row's state: green stripe, red none, grey unknown) to be inspected by eye.

How a reference is made (semi-automatic, independent of the trackers under
test): the guide of an image is a set of hand-placed segments: rows ``r0..r1``
and either a guide column linear from ``c0`` to ``c1`` (read off the
photographs) or a column ``band``, in which case the guide is the median over
15 rows of each row's maximum within the band. In each
row of a segment, the tracker frame (the manifest's channel, ``excess`` of the
laser colour by default, turned by ``rotate``) is searched within
``half_width`` px of the guide for its maximum; the row gets a reference only
if that maximum stands ``min_contrast`` x (robust noise of the frame) above the
median of the window; the reference column is the contrast-weighted centroid of
the pixels above half that contrast within 3 px of the maximum, or, for wide
saturated stripes (``level`` given), of the run of pixels above ``level`` x the
contrast around the maximum (the middle of the saturated plateau). Rows outside every
segment, and rows in ``exclude`` ranges, have no reference.

Row states (the third column of ``NAME_ref.csv``): a row with a reference column is
``stripe``; a row in one of the guide's ``none`` ranges is ``none`` (no laser light of
the stripe in that row of the tracker's frame: a report there is a false one); every
other row is ``unknown`` (the stripe may be there, too dim, ambiguous or occluded to
be sure: not scored). The ``none`` ranges were each checked by eye on the photograph
and its check overlay, and declared only where the stripe is surely absent (above the
object the laser reaches, in a gap the stripe visibly leaves); rows where the laser
crosses clutter in a room without a visible line stay ``unknown``. Every ``none`` row of a guide
must also pass :func:`bench.evaluate.nonerows.doubtful_rows` (no faint continuation of the stripe's
path, no reflection as narrow as the stripe, no ridge of the laser's colour); a row it flags is
written ``unknown``.
"""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "bench" / "data" / "real"
CHECKS = ROOT / "docs" / "real"

# NAME -> (source file in SRC_DIR, downscale factor, crop (r0, r1, c0, c1) of the source or None)
SOURCES = {
    "al_frame": ("frame.jpg", 8, None),
    **{f"al_room{i}": ("stitch.jpg", 4, (0, 1920, i * 1098, (i + 1) * 1098)) for i in range(10)},
    "ag_tape": ("test-img.png", 1, None),
    "dg_weld": ("weld2.png", 2, None),
    "rb_figure1": ("img_5014.jpg", 2, None),
    "rb_figure1_off": ("img_5013.jpg", 2, None),
    "rb_figure2": ("img_5397.jpg", 2, None),
    "rb_figure2_off": ("img_5396.jpg", 2, None),
    "bb_speaker": ("l5.jpg", 8, None),
    "bb_dark": ("l1.jpg", 8, None),
    "bb_board": ("brightness_15cm_0.png", 1, None),
    "bb_hand": ("test_1.png", 1, None),
    "jz_chair": ("test.jpg", 2, (2, 1012, 18, 1366)),  # the frame's black left band and top rows cut off
    **{f"fh_{side}{step}{off}": (f"{step:02d}-{'off' if off else side}.png", 3, None)
       for step in (0, 16) for side in ("left", "right") for off in ("", "_off")},
    # chrisspen/laser-range-finder: 320x240 frames, laser on (b) and off (a); the odd samples 1-9
    **{f"cs_{what}{off}": (f"chrisspen/sample{i}-{'a' if off else 'b'}-0.jpg", 1, None)
       for i, what in ((1, "room"), (3, "soap"), (5, "shoe_dark"), (7, "shoe"), (9, "desk")) for off in ("", "_off")},
    # octopusengine/simple3dscanner: the photograph tiles of two collages (the other tiles show hardware or output)
    "oe_skull": ("octopusengine/first-scann--it-works.jpg", 1, (0, 626, 790, 1330)),  # its top-right tile, left 540 px
    "oe_figure": ("octopusengine/example-of-processing.jpg", 2, (0, 1114, 0, 756)),  # its left tile
    # Agent5/3D-scanner: frames 001 and 061 (0 and 180 degrees) of each of its three 120-frame raw scans
    **{f"a5_{what}{deg}": (f"agent5/{scan}_raw_image-{i}.png", 1, None)
       for scan, what in (("35mm_cube", "cube"), ("ceremic_doll", "doll"), ("day_lilly", "lily"))
       for i, deg in (("001", 0), ("061", 180))},
    # capopaul/3D-Scanner-Using-Laser-Triangulation: the two photographs among its slide images
    "cp_wall": ("capopaul/no_deformation.png", 1, None),
    "cp_box": ("capopaul/deformation.png", 1, (92, 644, 922, 1402)),  # the photograph on the slide's right
    # Raldir/3DScanner.RaspberryPi: the laser-on photographs of core/fotos that have a laser-off frame of the same view ...
    "rd_horus": ("raldir/img01.jpg", 5, None),
    "rd_horus_off": ("raldir/img00.jpg", 5, None),
    "rd_horus2": ("raldir/img1.jpg", 5, None),
    "rd_horus2_off": ("raldir/img0.jpg", 5, None),
    # ... and frames 0, 2 and 4 of its horizontal scan in the dark (core/fotos/0.jpg .. 4.jpg)
    **{f"rd_dark{i}": (f"raldir/core_fotos_{i}.jpg", 4, None) for i in (0, 2, 4)},
    "hx_thin": ("hexastorm/laserline.jpg", 2, None),
    "hx_wide": ("hexastorm/laserline1.jpg", 3, None),
    "lm_wheel": ("lasermat/C0_p240_SD.png", 6, (0, 1800, 0, 4096)),  # the rows below 1800 hold no laser light
    "lm_gage": ("lasermat/gage.jpg", 3, None),
    # triangulation_3's frames are 640x480 (a third of triangulation_4's width): full size keeps the scale of the
    # fh_* frames above; the left laser's half only (columns 0-312: the two lines meet on the box at 313-327)
    **{f"fh_box{step:02d}{off}": (f"fhennecker/t3_{step + (1 if off else 0):02d}.png", 1, (0, 480, 0, 313))
       for step in (4, 34, *range(8, 49, 4)) for off in ("", "_off")},
    "bb_small": ("b33boy/l3.jpg", 8, None),
    "bb_night": ("b33boy/l4.jpg", 8, None),
    "hx_dash1": ("hexastorm/2021-01-22-15-11.jpg", 2, None),
    "hx_dots1": ("hexastorm/2021-01-22-15-26.jpg", 2, None),
    "hx_dots2": ("hexastorm/2021-01-22-15-27.jpg", 2, None),
    "hx_dash2": ("hexastorm/2021-01-22-15-52.jpg", 2, None),
}


#: Photographs whose source has a thin black line drawn over its stripe (a tracker's output saved with the frame): the
#: line is found and its darkening undone (:func:`bench.evaluate.overlay.line_pixels`, :func:`~bench.evaluate.overlay.
#: undo_line`), so that what is shipped is the camera's pixels (docs/real.md, "A line drawn over `ag_tape`'s stripe")
DRAWN_LINE = ("ag_tape",)


def _downscale(a: np.ndarray, f: int) -> np.ndarray:
    from skimage.transform import downscale_local_mean

    a = (a if a.ndim == 2 else a[..., :3]).astype(np.float64)  # a grey source stays one channel
    if f == 1:
        return np.clip(np.rint(a), 0, 255).astype(np.uint8)
    H, W = (a.shape[0] // f) * f, (a.shape[1] // f) * f
    block = (f, f) if a.ndim == 2 else (f, f, 1)
    return np.clip(np.rint(downscale_local_mean(a[:H, :W], block)), 0, 255).astype(np.uint8)


def make_images(src: Path, names=None) -> None:
    """Write ``NAME.png`` for each of ``names`` (default: every name of :data:`SOURCES`) from ``src``."""
    import imageio.v3 as iio

    unknown = sorted(set(names or ()) - set(SOURCES))
    if unknown:
        raise SystemExit(f"make_real_set.py images: unknown names {', '.join(unknown)} (known: {', '.join(SOURCES)})")
    for name, (fname, f, crop) in SOURCES.items():
        if names and name not in names:
            continue
        a = np.asarray(iio.imread(src / fname))
        if crop is not None:
            r0, r1, c0, c1 = crop
            a = a[r0:r1, c0:c1]
        out = _downscale(a, f)
        undone = ""
        if name in DRAWN_LINE:
            from bench.evaluate.overlay import line_pixels, undo_line

            pixels = line_pixels(out)
            out = undo_line(out, pixels)
            undone = f", a drawn line undone in {len(pixels)} pixels of {len({r for r, _, _ in pixels})} rows"
        iio.imwrite(DATA / f"{name}.png", out)
        print(f"{name}.png {out.shape[1]}x{out.shape[0]} from {fname} (1/{f}){undone}")


def reference_for(frame: np.ndarray, guide: dict) -> np.ndarray:
    """Reference columns (H,) of one frame from its guide (see the module docstring)."""
    from bench.evaluate.outcomes import REFERENCE_HALF_WIDTH, REFERENCE_MIN_CONTRAST, reference_noise, window_centre

    H, W = frame.shape
    f = frame.astype(np.float64)
    noise = reference_noise(f)  # the rule's home: bench.evaluate.outcomes (also scores renders like photographs)
    hw = int(guide.get("half_width", REFERENCE_HALF_WIDTH))
    k = float(guide.get("min_contrast", REFERENCE_MIN_CONTRAST))
    level = float(guide["level"]) if "level" in guide else None
    ref = np.full(H, np.nan)
    for seg in guide["segments"]:
        r0, r1 = seg["rows"]
        r0, r1 = max(0, r0), min(H - 1, r1)
        seg_hw = int(seg.get("half_width", hw))
        if "cols" in seg:  # a hand-placed line
            c0, c1 = seg["cols"]
            guide_cols = c0 + (c1 - c0) * ((np.arange(r0, r1 + 1) - r0) / max(r1 - r0, 1))
        else:  # the rows' maxima within `band`, median over 15 rows
            from scipy.ndimage import median_filter

            lo_b, hi_b = seg.get("band", [0, W - 1])
            guide_cols = lo_b + np.argmax(f[r0:r1 + 1, lo_b:hi_b + 1], axis=1).astype(np.float64)
            guide_cols = median_filter(guide_cols, size=15, mode="nearest")
        for r in range(r0, r1 + 1):
            g = guide_cols[r - r0]
            lo, hi = max(0, int(round(g)) - seg_hw), min(W, int(round(g)) + seg_hw + 1)
            if hi - lo < 3:
                continue
            win = f[r, lo:hi]
            if float(win.max()) - float(np.median(win)) < k * noise:
                continue
            ref[r] = lo + window_centre(win, level)  # the rule's home: bench.evaluate.outcomes
    for e0, e1 in guide.get("exclude", []):
        ref[max(0, e0):e1 + 1] = np.nan
    return ref


def difference_guide(on, off, laser: str = "red", *, skip_cols: int = 0, min_k: float = 8.0, rival_k: float = 6.0,
                     rival_px: int = 25, jump_px: int = 4, run_rows: int = 8, line_rows: int = 12) -> list[dict]:
    """Guide segments (``{"rows": [r0, r1], "cols": [c0, c1]}``) read off a laser-on minus laser-off difference.

    The difference is taken in the laser colour's excess (its channel minus the mean of the other two, not clipped),
    its noise is the MAD of the whole difference, and columns under ``skip_cols`` are then set to 0 (a window whose
    daylight changes between the two frames). A row is guided where its maximum stands ``min_k`` noise units up and
    nothing ``rival_px`` px or more from it reaches ``rival_k`` (one lit piece, not two); runs of such rows whose
    maxima move at most ``jump_px`` px from row to row, ``run_rows`` rows or more, get one line per ``line_rows`` rows
    (a shorter last piece joins the line before it), drawn between the run's 5-row median maxima at its ends. Used
    for the ``fh_*`` frames (docs/real.md, "How the references were made"); the reference rule then finds each row's
    column on the tracker frame near the line, as for a hand-placed guide.

    Parameters
    ----------
    on, off : ndarray, shape (H, W, 3)
        The laser-on photograph and its laser-off frame (DN).

    Returns
    -------
    list of dict
        The segments, top to bottom.
    """
    from scipy.ndimage import median_filter

    from bench.evaluate.pixels import LASERS

    k = LASERS.index(laser)
    others = [i for i in range(3) if i != k]

    def excess(x):
        x = np.asarray(x, dtype=np.float64)
        return x[..., k] - 0.5 * (x[..., others[0]] + x[..., others[1]])

    d = excess(on) - excess(off)
    H = d.shape[0]
    noise = 1.4826 * np.median(np.abs(d - np.median(d)))
    if noise <= 0.0:  # the two frames are (nearly everywhere) the same: no laser line to guide by
        return []
    d[:, :skip_cols] = 0.0
    peak = np.argmax(d, axis=1)
    height = d[np.arange(H), peak] / noise
    rival = np.empty(H)
    for r in range(H):
        m = d[r].copy()
        m[max(0, peak[r] - rival_px):peak[r] + rival_px + 1] = -np.inf
        rival[r] = m.max() / noise
    ok = (height >= min_k) & (rival < rival_k)
    segments, r = [], 0
    while r < H:
        if not ok[r]:
            r += 1
            continue
        r0 = r
        while r + 1 < H and ok[r + 1] and abs(int(peak[r + 1]) - int(peak[r])) <= jump_px:
            r += 1
        if r - r0 + 1 >= run_rows:
            cols = median_filter(peak[r0:r + 1].astype(np.float64), size=5, mode="nearest")
            starts = list(range(r0, r + 1, line_rows))
            if r - starts[-1] < 2 and len(starts) > 1:  # a last piece of one or two rows joins the line before it
                starts.pop()
            for i, q0 in enumerate(starts):
                q1 = starts[i + 1] - 1 if i + 1 < len(starts) else r
                segments.append({"rows": [q0, q1], "cols": [int(round(cols[q0 - r0])), int(round(cols[q1 - r0]))]})
        r += 1
    return segments


def states_for(ref: np.ndarray, guide: dict) -> np.ndarray:
    """Row states (H,) int8: stripe where ``ref`` has a column, none in the guide's ``none`` ranges, else unknown."""
    from bench.evaluate.outcomes import NO_STRIPE, STRIPE, UNSURE

    states = np.full(ref.size, UNSURE, dtype=np.int8)
    for n0, n1 in guide.get("none", []):
        states[max(0, n0):n1 + 1] = NO_STRIPE
    states[~np.isnan(ref)] = STRIPE
    return states


def none_doubts(frame: np.ndarray, ref: np.ndarray, states: np.ndarray, original: np.ndarray, laser: str,
                rotate_deg: int, off=None, off_original=None) -> np.ndarray:
    """The guide's ``none`` rows that :func:`bench.evaluate.nonerows.doubtful_rows` finds a sign of the stripe in
    (bool (H,)): on the reference's frame and, for a colour photograph, its laser colour's excess; in their
    laser-on minus laser-off difference where the laser-off frame (``off``, read as ``frame``; ``off_original`` as
    ``original``) is given."""
    from bench.evaluate.nonerows import doubtful_rows
    from bench.evaluate.pixels import rotate_image, select_channel

    def excess(img):
        o = np.asarray(img)
        grey = o.ndim == 2 or (np.array_equal(o[..., 0], o[..., 1]) and np.array_equal(o[..., 0], o[..., 2]))
        return None if grey else rotate_image(select_channel(o, "excess", laser), rotate_deg)

    colour = excess(original)
    colour_off = None if off_original is None or colour is None else excess(off_original)
    flags = doubtful_rows(frame, ref, states, colour=colour, background=off, colour_background=colour_off)
    return np.logical_or.reduce(list(flags.values()))


def state_bar(img: np.ndarray, states: np.ndarray, rotate_deg: int) -> np.ndarray:
    """``img`` (the photograph's orientation) with each tracker-frame row's state as a 6-px bar at the
    frame's left edge (green stripe, red none, grey unknown)."""
    colours = {1: (0, 200, 0), 0: (230, 0, 0), -1: (128, 128, 128)}
    k = rotate_deg // 90
    frame = np.rot90(np.asarray(img), k=k).copy()  # the tracker's frame: the photograph turned counter-clockwise
    frame[:, :6] = np.array([colours[int(st)] for st in states], dtype=np.uint8)[:, None, :]
    return np.ascontiguousarray(np.rot90(frame, k=-k))


def make_refs() -> None:
    import imageio.v3 as iio

    from bench.evaluate.outcomes import STATE_NAMES, UNSURE, fallback_states
    from bench.report.real import overlay
    from bench.store import realset as real

    guides = tomllib.loads((DATA / "guides.toml").read_text())
    import csv

    rows = {r["name"]: r for r in csv.DictReader((DATA / "manifest.csv").read_text().splitlines())}
    CHECKS.mkdir(parents=True, exist_ok=True)
    for name, row in rows.items():
        rot = int(row.get("rotate") or 0)
        channel = row.get("channel") or "auto"
        # the references are found on the laser's colour excess where the manifest says `auto` (what
        # `auto` meant when they were made; the saturation knee came later and would move them)
        frame, original = real.load_frame(DATA / f"{name}.png", channel="excess" if channel == "auto" else channel,
                                          laser=row["laser_colour"], rotate_deg=rot)
        ref = reference_for(frame, guides[name])
        states = states_for(ref, guides[name])
        off = off_original = None
        if (row.get("has_background") or "0").strip() == "1":
            off, off_original = real.load_frame(DATA / f"{name}_off.png",
                                                channel="excess" if channel == "auto" else channel,
                                                laser=row["laser_colour"], rotate_deg=rot)
        doubt = none_doubts(frame, ref, states, original, row["laser_colour"], rot, off, off_original)
        states[doubt] = UNSURE
        lines = ["row,col,state"] + [f"{i}," + ("" if np.isnan(c) else f"{c:.2f}") + f",{STATE_NAMES[int(st)]}"
                                     for i, (c, st) in enumerate(zip(ref, states))]
        (DATA / f"{name}_ref.csv").write_text("\n".join(lines) + "\n")
        img = overlay(original, {}, rotate_deg=rot, reference=ref, dim=0.5)
        iio.imwrite(CHECKS / f"{name}_ref.png", state_bar(img, states, rot))
        fb = fallback_states(ref)
        print(f"{name}: {int(np.sum(states == 1))} stripe, {int(np.sum(states == 0))} none, "
              f"{int(np.sum(states == -1))} unknown of {ref.size} rows (the fallback rule: "
              f"{int(np.sum(fb == 0))} none, {int(np.sum(fb == -1))} unknown)"
              + (f"; {int(doubt.sum())} none rows of the guide in doubt, written unknown" if doubt.any() else ""))


def print_difference_guides(names, *, skip_cols: int = 0, min_k: float = 8.0, rival_k: float = 6.0) -> None:
    """Print each photograph's :func:`difference_guide` segments as ``guides.toml`` holds them: rows and columns of
    the tracker's frame (both photographs turned by the manifest's ``rotate``)."""
    from bench.store import realset as real

    images = {im.name: im for im in real.load_dataset(DATA)}  # the set's manifest, read and checked in one place
    for name in names:
        im = images.get(name)
        if im is None or im.background_path is None:
            raise SystemExit(f"make_real_set.py guides: {name!r} is not a shipped photograph with a laser-off frame")
        on, off = (real.rotate_image(real.read_image(p), im.rotate_deg) for p in (im.image_path, im.background_path))
        segs = difference_guide(on, off, im.laser_colour, skip_cols=skip_cols, min_k=min_k, rival_k=rival_k)
        print(f"[{name}]\nsegments = [" + ",\n            ".join(
            f"{{rows = [{g['rows'][0]}, {g['rows'][1]}], cols = [{g['cols'][0]}, {g['cols'][1]}]}}" for g in segs) + "]")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("images")
    s.add_argument("src", type=Path)
    s.add_argument("names", nargs="*", help="only these images (default: all)")
    sub.add_parser("refs")
    s = sub.add_parser("guides", help="print guide segments read off the laser-on minus laser-off difference")
    s.add_argument("names", nargs="+", help="photographs of the shipped set with a NAME_off.png")
    s.add_argument("--skip-cols", type=int, default=0, help="columns left of this are left out (default 0)")
    s.add_argument("--min-k", type=float, default=8.0, help="a guided row's peak, in noise units (default 8)")
    s.add_argument("--rival-k", type=float, default=6.0,
                   help="no second piece 25 px or more away may reach this, in noise units (default 6)")
    args = p.parse_args(argv)
    if args.cmd == "images":
        make_images(args.src, args.names)
    elif args.cmd == "guides":
        print_difference_guides(args.names, skip_cols=args.skip_cols, min_k=args.min_k, rival_k=args.rival_k)
    else:
        make_refs()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
