"""The photographs of a prediction and the frames with truth made of each: its stripe moved both ways, and in place.

:func:`collect_photos` reads a folder (a real set's manifest, or every image file with ``NAME_off.EXT`` laser-off
frames). :func:`transplanted` makes a photograph's frames (:func:`transplant_frames`; :mod:`bench.evaluate.stripe`,
:mod:`bench.evaluate.transplant`, :mod:`bench.evaluate.rowstates`) or says why it cannot (the photograph is then *out
of range*); :func:`transplant_outcomes` scores the trackers on them as a photograph is scored. Every tuned value is a
field of :class:`bench.evaluate.predict_settings.PredictSettings` (``settings``).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.evaluate import conditions as cond
from bench.evaluate.predict_settings import DEFAULT, PredictSettings

__all__ = ["Photo", "collect_photos", "photo_conditions", "score_frame", "transplant_frames", "photo_extents",
           "colour_guide", "transplanted", "cut_counts", "transplant_outcomes", "N_MOVED", "N_FULL", "PhotoFile",
           "photo_files", "load_photo"]

#: The first N_MOVED frames of :func:`transplant_frames` are the moved frames; the next is the photograph in place. Hit
#: rate and F1 are read from those N_FULL; any after them are false-report frames (only their stripe-less rows are
#: scored, and only the false-report rate reads them: they would change F1's mix of stripe and stripe-less rows, which
#: is the photograph's in the first N_FULL).
N_MOVED = 2
N_FULL = N_MOVED + 1



@dataclass
class Photo:
    """One photograph to predict for: the frame the trackers see, its laser-off frame, the original."""

    name: str
    path: Path
    frame: np.ndarray
    background: np.ndarray | None
    original: np.ndarray
    laser: str = "red"
    rotate_deg: int = 0
    channel: str = "auto"
    background_original: np.ndarray | None = None
    fallback_rows: bool = False
    """Whether the frames' rows are read as a reference without row states is read
    (:func:`bench.evaluate.outcomes.fallback_of`: every row not scored as a stripe row, at least ``GAP_ROWS`` from
    each that is, has no stripe): set for a real set whose ``NAME_ref.csv`` files give no ``state`` column, as
    ``stripebench real`` then scores its photographs; otherwise a row the stripe crosses unseen is not scored."""
    source: PhotoFile | None = None
    """Its file (:func:`load_photo` reads it again at another shrink)."""
    downscale: int = 1
    """The shrink it was read at."""

    @property
    def colour(self) -> bool:
        """A colour photograph (a grey picture stored as RGB is grey)."""
        o = self.original
        return o.ndim == 3 and not (np.array_equal(o[..., 0], o[..., 1]) and np.array_equal(o[..., 0], o[..., 2]))


def photo_conditions(frame, background=None, original=None, *, rotate_deg: int = 0, laser: str = "red",
                     settings: PredictSettings = DEFAULT):
    """The conditions of a photograph as the trackers see it (:func:`bench.evaluate.conditions.measure`).

    Parameters
    ----------
    frame, background : ndarray (H, W)
        The tracker's frame and laser-off frame (:func:`bench.store.realset.load_frame`).
    original : ndarray (H0, W0) or (H0, W0, 3)
        The photograph as read; a colour one is turned by ``rotate_deg`` and measured for colour.
    """
    from bench.evaluate.pixels import rotate_image

    rgb = None
    if original is not None and np.ndim(original) == 3:
        rgb = rotate_image(original, rotate_deg)
    return cond.measure(frame, background, rgb=rgb, laser=laser, settings=settings)


def score_frame(trackers: dict, image, truth_columns, background=None, states=None, colour=None) -> dict:
    """Label -> row outcomes (int8, shape (H,)) of each tracker on one frame with truth, scored as a
    photograph is: by default a stripe row only where the real set's reference rule sees the stripe
    in ``image`` (:func:`bench.evaluate.outcomes.referenced_states`), else not scored; rows without a
    stripe are scored. ``states`` (shape (H,)) replaces that reading. ``colour``: the frame's colour evidence
    (:func:`bench.run.camera_view.colour_of`), passed to the trackers as ``real`` passes a photograph's. A tracker
    that fails reports nothing."""
    from bench.evaluate.outcomes import referenced_states, row_outcomes
    from bench.run.track import track_frame

    states = referenced_states(image, truth_columns) if states is None else states
    out = {}
    for lab, t in trackers.items():
        r = track_frame(t, image, background, colour)
        cols = r.columns if r.ok else np.full(np.shape(image)[0], np.nan)
        out[lab] = row_outcomes(cols, truth_columns, states)
    return out


def transplant_frames(photo: Photo, *, seed: int = 0, measured=None, settings: PredictSettings = DEFAULT) -> list:
    """The photograph with its own stripe moved, both ways (:mod:`bench.evaluate.transplant`; the stripe found by
    :func:`photo_extents`); the photograph itself, its stripe where the estimate puts it
    (:func:`bench.evaluate.transplant.in_place_truth`: its own glow, rivals and surroundings, which a moved frame does
    not carry whole); and, where the stripe is long enough, two *false-report frames*: moved the same ways with its
    ends cut off (:func:`bench.evaluate.transplant.cut_ends`), in which only the stripe-less rows are scored (their
    stripe rows are ``UNSURE``): the hit rate is read from the first three frames alone (:data:`N_FULL`), the
    false-report rate from the stripe-less rows of all five. ``measured``: the frame's conditions, when the caller has
    them. A frame out of the transplant's range (:func:`bench.evaluate.stripe.out_of_range`) is the caller's to leave
    out, with its reason.

    Returns
    -------
    list
        ``[(image, truth, states, moved, shift_px), ...]`` (three or five; the photograph in place third, with
        ``shift_px`` 0): the tracker's frame of the moved photograph (:func:`bench.evaluate.pixels.select_channel`
        with the photograph's channel and laser), the moved stripe's columns (px, NaN where not moved), its row states
        (:func:`bench.evaluate.rowstates.row_states`; with :attr:`Photo.fallback_rows`, read by
        :func:`bench.evaluate.outcomes.fallback_of`), the moved photograph (turned as the frame) and the shift; empty
        when the moved stripe is seen (by the reference rule) in fewer than ``min_rows`` rows of the two moved frames
        together: too few to predict from (no visible stripe, or one much wider than the reference window).
    """
    from bench.evaluate import rowstates as rs
    from bench.evaluate import stripe as sp
    from bench.evaluate import transplant as tp
    from bench.evaluate.outcomes import STRIPE, UNSURE, fallback_of
    from bench.evaluate.pixels import LASER_INDEX, select_channel

    s = settings
    ext, original, bg_original = photo_extents(photo, measured=measured, settings=s)
    if not ext.visible.any():
        return []
    rivals = tp.rival_mask(photo.frame, photo.background, ext, settings=s)
    right, left = tp.shifts_for(ext, rivals, settings=s)
    noise = sp.channel_noise(original, settings=s)  # the clean plate's noise and the clipping margin (transplant)
    # the moved rows a reference would leave out (row_states): dim ones, visible or not
    unclear = rs.unclear_rows(ext, original, noise, guided=True, settings=s)
    # a clipped core in a glow of the surface's is a stripe row, as the references read it
    seen = rs.clipped_peaks(original, ext, noise, settings=s) & rs.glow_rows(photo.frame, ext, settings=s)

    def read(states):  # as the photograph's references read rows without a stripe (Photo.fallback_rows)
        return fallback_of(states) if photo.fallback_rows else states

    out = []
    # the laser's channel: near the top its moved lift is at least the others' (transplant's laser_channel)
    li = LASER_INDEX[photo.laser] if np.ndim(original) == 3 else None
    for j, shift in enumerate((right, -left)):
        moved, truth = tp.transplant(original, ext, shift, background_original=bg_original, seed=seed + j,
                                     noise_dn=noise, laser_channel=li, settings=s)
        image = select_channel(moved, photo.channel, photo.laser)
        # rows where the moved stripe lands on a rival are not scored: the photograph's stripe stands beside it
        landed = tp.landed_rows(ext, rivals, shift, settings=s)
        states = rs.row_states(ext, truth, image, unclear=unclear | landed, seen=seen, settings=s)
        out.append((image, truth, read(states), moved, shift))
    # the photograph itself, its stripe where the estimate puts it: its own glow, rivals and surroundings
    truth = tp.in_place_truth(ext)
    states = rs.row_states(ext, truth, photo.frame, unclear=unclear, seen=seen, settings=s)
    out.append((photo.frame, truth, read(states), original, 0))
    keep = tp.cut_ends(ext, settings=s)
    if keep is not None:  # the false-report frames: the stripe's ends cut off, only stripe-less rows scored
        for j, shift in enumerate((right, -left)):
            moved, truth = tp.transplant(original, ext, shift, background_original=bg_original, seed=seed + 2 + j,
                                         noise_dn=noise, keep=keep, laser_channel=li, settings=s)
            image = select_channel(moved, photo.channel, photo.laser)
            states = read(rs.row_states(ext, truth, image, keep, unclear, seen, settings=s))
            states[states == STRIPE] = UNSURE
            out.append((image, truth, states, moved, shift))
    return out if sum(int(np.sum(st == STRIPE)) for _, _, st, _, _ in out[:N_MOVED]) >= s.min_rows else []


def photo_extents(photo: Photo, *, measured=None, settings: PredictSettings = DEFAULT) -> tuple:
    """A photograph's stripe as :func:`transplant_frames` finds it: on a colour photograph whose trackers see the
    laser's colour (``settings.colour_guided``), along :func:`colour_guide`; on another, by the frame's own guide
    (:func:`bench.evaluate.stripe.estimate_guide`). ``measured``: the frame's conditions, when the caller has them.

    Returns
    -------
    tuple
        ``(ext, original, background_original)``: the :class:`bench.evaluate.stripe.Extents` and the photograph and
        its laser-off frame (None without) turned as the frame.
    """
    from bench.evaluate import stripe as sp
    from bench.evaluate.pixels import rotate_image

    original = rotate_image(photo.original, photo.rotate_deg)
    bg_original = (None if photo.background_original is None
                   else rotate_image(photo.background_original, photo.rotate_deg))
    if photo.colour and photo.channel in settings.colour_guided:
        guide = colour_guide(photo, original, bg_original, measured, settings=settings)
    else:
        guide = sp.estimate_guide(photo.frame, photo.background, measured=measured, settings=settings)
    ext = sp.stripe_extents(photo.frame, photo.background, measured=measured, guide=guide, settings=settings)
    return ext, original, bg_original


def colour_guide(photo: Photo, original, background_original=None, measured=None, *,
                 settings: PredictSettings = DEFAULT) -> np.ndarray:
    """The guide of a colour photograph whose trackers see the laser's colour, shape (H,), px (NaN: no stripe): the
    ``auto`` guide found on the pure laser-colour excess (:func:`bench.evaluate.pixels.select_channel` ``excess``:
    white light, clipped or not, has none) and the ``auto`` guide of the tracker's frame (``measured``: its
    conditions), made one by :func:`bench.evaluate.colourguide.arbitrate`: the colour guide, the frame's where the
    colour finds no stripe, and where the two part, the one with the more
    :func:`bench.evaluate.colourguide.laser_evidence` (bright and of the laser's colour: neither a white lamp nor a
    surface of the laser's hue; its colour read as nought where :func:`bench.evaluate.colourguide.hue_hidden`, a glare
    clipped in two channels; the frame's own guide's read over both its row and the reference window around it, the
    colour's over its row). ``original`` and ``background_original``: the photograph and its laser-off frame, turned
    as the frame."""
    from bench.evaluate import colourguide as cg
    from bench.evaluate import stripe as sp
    from bench.evaluate.pixels import LASER_INDEX, select_channel

    s = settings

    def parts(image):
        if image is None:
            return None, None
        return (np.asarray(image, dtype=np.float64)[..., LASER_INDEX[photo.laser]],
                select_channel(image, "excess", photo.laser))

    laser, excess = parts(original)
    laser_bg, excess_bg = parts(background_original)
    on_colour = sp.estimate_guide(excess, excess_bg, settings=s)
    own = sp.estimate_guide(photo.frame, photo.background, measured=measured, settings=s)
    # a pixel whose laser channel is clipped with another shows no hue: the arbiter reads no laser colour there
    coloured = np.where(cg.hue_hidden(original, photo.laser, settings=s), 0.0, excess)
    by_row = cg.laser_evidence(laser, coloured, laser_bg, excess_bg, settings=s)
    # the frame's own guide must stand out of the window around it too, not only of its row: read on the lesser (a
    # glare or lit patch wider than the window has little)
    by_window = cg.laser_evidence(laser, coloured, laser_bg, excess_bg, over="window", settings=s)
    return cg.arbitrate(on_colour, own, by_row, np.minimum(by_row, by_window), settings=s)


def transplanted(photo: Photo, *, seed: int = 0, measured=None, settings: PredictSettings = DEFAULT) -> tuple:
    """:func:`transplant_frames` of a photograph in the transplant's range, else why not: ``(frames, ())``, or
    ``([], ("width_px",))`` for a stripe wider than the reference window (:func:`bench.evaluate.stripe.out_of_range`,
    not moved at all) or ``([], ("visible",))`` for a moved stripe seen in too few rows. ``measured``: the
    photograph's conditions (measured here when None)."""
    from bench.evaluate import stripe as sp

    measured = cond.measure(photo.frame, photo.background, settings=settings) if measured is None else measured
    bad = sp.out_of_range(measured, settings=settings)
    if bad:
        return [], bad
    made = transplant_frames(photo, seed=seed, measured=measured, settings=settings)
    return (made, ()) if made else ([], ("visible",))


def cut_counts(per_frame: list) -> dict:
    """``n_false_cut`` and ``n_quiet_cut``: the false-report frames' stripe-less rows among one tracker's outcome
    arrays of one photograph (:func:`transplant_outcomes`; frames after :data:`N_FULL`).

    Examples
    --------
    >>> from bench.evaluate.outcomes import FALSE, HIT, QUIET
    >>> cut_counts([np.array([HIT]), np.array([HIT]), np.array([HIT]), np.array([FALSE, QUIET, QUIET])])
    {'n_false_cut': 1, 'n_quiet_cut': 2}
    """
    from bench.evaluate.outcomes import outcome_counts

    extra = [np.ravel(c) for c in per_frame[N_FULL:]]
    counts = outcome_counts(np.concatenate(extra)) if extra else {"n_false": 0, "n_quiet": 0}
    return {"n_false_cut": int(counts["n_false"]), "n_quiet_cut": int(counts["n_quiet"])}


def transplant_outcomes(trackers: dict, made: list, background=None, laser: str | None = None) -> dict:
    """Label -> row outcomes (one array per frame) of each tracker on :func:`transplant_frames`' frames
    ``made``, each read with its own row states (:func:`score_frame`) and, with the ``laser``'s colour, given the
    colour evidence of its photograph (:func:`bench.run.camera_view.colour_of`; none for a grey one)."""
    from bench.run.camera_view import colour_of

    per = {lab: [] for lab in trackers}
    for image, truth, states, moved, _ in made:
        colour = None if laser is None else colour_of(moved, laser)  # the moved photograph is turned already
        for lab, codes in score_frame(trackers, image, truth, background, states, colour).items():
            per[lab].append(codes)
    return per


@dataclass(frozen=True)
class PhotoFile:
    """Where a photograph to predict for is and how it is read: its file and laser-off file, the tracker's channel, the
    laser's colour, the turn, and its real set's reference (whose header says whether it gives row states)."""

    name: str
    path: Path
    background_path: Path | None
    channel: str
    laser: str
    rotate_deg: int
    reference_path: Path | None = None


def photo_files(folder, *, channel: str = "auto", laser: str = "red", rotate_deg: int = 0, err=None) -> list:
    """The photographs of ``folder`` (:class:`PhotoFile`): a real set's, as its manifest says (its laser, channel
    and rotation), or every image file with the given ``channel``, ``laser`` and ``rotate_deg`` (``NAME_off.EXT``
    paired as ``NAME``'s laser-off frame; a laser-off frame without a partner gets one line on ``err``).

    Raises
    ------
    bench.store.realset.ImageError
        ``folder`` is not a folder; a manifest that is not a valid real set's (a row with a bad value, a column
        missing: one line, the first problem, as ``stripebench real`` says it); two image files that would both be
        called ``NAME`` (``a.png`` and ``a.jpg``).
    """
    from bench.store import realset as real

    err = sys.stderr if err is None else err
    root = Path(folder)
    if not root.is_dir():
        raise real.ImageError(f"{str(root)!r}: not a folder")
    if (root / "manifest.csv").is_file():
        images, problems = real.validate_dataset(root)
        if problems:
            more = (f" (and {len(problems) - 1} more; `stripebench real DATASET --check` lists them)"
                    if len(problems) > 1 else "")
            raise real.ImageError(f"{str(root)!r} has a manifest.csv but is not a valid real set: {problems[0]}{more}")
        return [PhotoFile(im.name, im.image_path, im.background_path, im.channel, im.laser_colour, im.rotate_deg,
                          im.reference_path) for im in images]
    files = sorted(p for p in root.iterdir() if p.is_file() and p.suffix.lower() in real.IMAGE_SUFFIXES)
    by_stem: dict = {}
    for p in files:
        by_stem.setdefault(p.stem, []).append(p.name)
    twins = {s: n for s, n in by_stem.items() if len(n) > 1}
    if twins:
        stem, names = next(iter(twins.items()))
        raise real.ImageError(f"{str(root)!r}: {' and '.join(names)} would both be the photograph {stem!r}: rename "
                              "one (a photograph is named by its file name without the extension)")
    out = []
    for p in files:
        if p.stem.endswith("_off"):
            if p.stem[:-4] not in by_stem:  # a laser-off frame is no photograph: say so when it has no partner
                print(f"stripebench predict: {p.name}: a laser-off frame with no photograph {p.stem[:-4]}.* "
                      "beside it: not predicted for", file=err)
            continue
        out.append(PhotoFile(p.stem, p, real.background_for(p), channel, laser, rotate_deg))
    return out


def load_photo(source: PhotoFile, *, downscale: int = 1, settings: PredictSettings = DEFAULT) -> Photo:
    """The photograph ``source`` as the trackers see it, each ``downscale`` x ``downscale`` block of pixels averaged
    into one (:func:`bench.store.realset.load_frame`; 1: as it is).

    Raises
    ------
    bench.store.realset.ImageError
        An unreadable file, a laser-off frame of another shape, or a frame smaller than ``settings.min_frame_px``.
    """
    from bench.store import realset as real

    if isinstance(downscale, bool) or not isinstance(downscale, (int, np.integer)) or downscale < 1:
        raise ValueError(f"`downscale` must be an integer >= 1, got {downscale!r}")
    s = source
    frame, original = real.load_frame(s.path, channel=s.channel, laser=s.laser, rotate_deg=s.rotate_deg,
                                      downscale=downscale)
    least = settings.min_frame_px
    if frame.shape[0] < least[0] or frame.shape[1] < least[1]:
        raise real.ImageError(f"{str(s.path)!r}: its frame is {frame.shape[0]} x {frame.shape[1]} px, too small "
                              f"to predict for (at least {least[0]} rows and {least[1]} columns)")
    bg = bg_original = None
    if s.background_path is not None:
        bg, bg_original = real.load_frame(s.background_path, channel=s.channel, laser=s.laser,
                                          rotate_deg=s.rotate_deg, downscale=downscale)
        if bg.shape != frame.shape:
            raise real.ImageError(f"{str(s.path)!r}: laser-off frame {s.background_path.name} has shape {bg.shape}, "
                                  f"the image {frame.shape}")
    # the states' convention from the reference's header alone, never the labels
    given = True if s.reference_path is None else real.reference_gives_states(s.reference_path)
    return Photo(s.name, Path(s.path), frame, bg, original, s.laser, s.rotate_deg, s.channel, bg_original,
                 fallback_rows=not given, source=s, downscale=int(downscale))


def collect_photos(folder, *, channel: str = "auto", laser: str = "red", rotate_deg: int = 0, downscale: int = 1,
                   err=None, settings: PredictSettings = DEFAULT) -> list[Photo]:
    """The photographs of ``folder`` (:func:`photo_files`) read (:func:`load_photo`) at ``downscale``. An
    unreadable file gets one line on ``err`` and is left out, as is a frame smaller than ``settings.min_frame_px``; a
    file whose EXIF orientation asks for a turn its ``rotate_deg`` does not give gets one line too
    (:func:`bench.store.realset.orientation_note`: read as stored).

    Raises
    ------
    bench.store.realset.ImageError
        As :func:`photo_files`.
    """
    from bench.store import realset as real

    if isinstance(downscale, bool) or not isinstance(downscale, (int, np.integer)) or downscale < 1:
        raise ValueError(f"`downscale` must be an integer >= 1, got {downscale!r}")
    err = sys.stderr if err is None else err
    photos = []
    for source in photo_files(folder, channel=channel, laser=laser, rotate_deg=rotate_deg, err=err):
        try:
            photo = load_photo(source, downscale=downscale, settings=settings)
        except (real.ImageError, real.DatasetError) as exc:
            print(f"stripebench predict: {exc}", file=err)
            continue
        note = real.orientation_note(source.path, source.rotate_deg)
        if note:
            print(f"stripebench predict: {note}", file=err)
        photos.append(photo)
    return photos
