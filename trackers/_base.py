"""The tracker interface: :class:`Track` and :class:`Tracker`."""

from __future__ import annotations

import abc
import inspect
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ._validation import check_background, check_colour, check_image

__all__ = ["Track", "Tracker"]


@dataclass(frozen=True, eq=False)
class Track:
    """The stripe found in one frame.

    Attributes
    ----------
    columns : ndarray of float64, shape (H,)
        Sub-pixel column of the stripe in each image row (row 0 at the top), in
        pixel units where an integer is the centre of that pixel. NaN where the
        tracker reports no stripe.
    score : ndarray of float64, shape (H,)
        The tracker's own confidence per row: higher is more confident, finite
        wherever a column is reported and NaN exactly where ``columns`` is NaN.
        The benchmark ranks a tracker's reports by it (average precision over
        rows), so only its order matters; its units are documented per tracker
        (the conformance suite checks the order: ``check_score_meaning``).

    Both arrays are stored read-only.
    """

    columns: np.ndarray
    score: np.ndarray

    def __post_init__(self):
        cols = np.array(self.columns, dtype=np.float64, copy=True)
        score = np.array(self.score, dtype=np.float64, copy=True)
        if cols.ndim != 1:
            raise ValueError(f"`columns` must be 1-D, got shape {cols.shape}")
        if score.shape != cols.shape:
            raise ValueError(f"`score` must have the shape of `columns` {cols.shape}, got {score.shape}")
        if np.isinf(cols).any():
            raise ValueError("`columns` must be finite or NaN, got infinite value(s)")
        if np.isinf(score).any():
            raise ValueError("`score` must be finite or NaN, got infinite value(s)")
        missing = np.isnan(cols)
        if not np.array_equal(missing, np.isnan(score)):
            raise ValueError("`score` must be NaN exactly where `columns` is NaN")
        cols.flags.writeable = False
        score.flags.writeable = False
        object.__setattr__(self, "columns", cols)
        object.__setattr__(self, "score", score)

    @property
    def height(self) -> int:
        """Number of image rows."""
        return int(self.columns.shape[0])

    @property
    def detected(self) -> np.ndarray:
        """Boolean mask (H,) of the rows with a reported stripe."""
        return ~np.isnan(self.columns)

    @classmethod
    def empty(cls, height: int) -> "Track":
        """A track that reports nothing in any of ``height`` rows."""
        nan = np.full(height, np.nan)
        return cls(nan, nan)


_TAKES_COLOUR: dict = {}


def _takes_colour(cls) -> bool:
    """Whether ``cls.uses_colour`` and its ``find_stripe`` takes a third argument (the colour evidence)."""
    if cls not in _TAKES_COLOUR:
        import inspect

        ok = bool(getattr(cls, "uses_colour", False))
        if ok:
            try:
                params = list(inspect.signature(cls.find_stripe).parameters.values())
            except (TypeError, ValueError):
                params = []
            ok = any(p.kind == p.VAR_POSITIONAL for p in params) or len(
                [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]) >= 4
        _TAKES_COLOUR[cls] = ok
    return _TAKES_COLOUR[cls]


class Tracker(abc.ABC):
    """Base class of every stripe tracker.

    Subclasses declare their parameters as keyword arguments of ``__init__``
    and store them unchanged under the same attribute names (scikit-learn's
    rule: no validation and no work in the constructor; parameters are
    validated when :meth:`track` is called), declare each parameter's
    constraint in :attr:`parameter_constraints`, and override
    :meth:`find_stripe` (the public hook; older trackers override ``_track``,
    which :meth:`find_stripe` calls by default). Rules that tie parameters
    together go in an override of :meth:`validate_params` that calls
    ``super().validate_params()``. See ``docs/plugins.md``.

    Class attributes
    ----------------
    name : str
        The registered name (``trackers.make(name)``).
    subpixel : bool
        Whether the tracker claims sub-pixel precision (the conformance suite
        holds sub-pixel trackers to 0.1 px and the others to 0.6 px mean
        absolute error on a synthetic stripe).
    uses_background : bool
        Whether the tracker uses the laser-off frame when one is given (the
        conformance suite then also checks it with one: an ambient
        distractor present in both frames must not be tracked, and a
        laser-off frame equal to the laser-on frame leaves nothing to find).
    uses_colour : bool
        Whether the tracker reads the frame's colour evidence (``track``'s
        ``colour``); its :meth:`find_stripe` then takes it as a third
        argument. Trackers without it never see it (the conformance suite
        checks that evidence carrying no information changes nothing).
    """

    name: ClassVar[str] = ""
    subpixel: ClassVar[bool] = False
    uses_background: ClassVar[bool] = False
    uses_colour: ClassVar[bool] = False
    #: parameter name -> its constraint (:class:`trackers._params.Real`, ``Int``, ``Choice``,
    #: ``Bool``): checked by :meth:`validate_params`, and by the conformance suite for every
    #: tracker that declares it (each parameter must have one; each constraint's invalid values
    #: must be refused, naming the parameter)
    parameter_constraints: ClassVar[dict] = {}

    def __new__(cls, *args, **kwargs):
        if cls.find_stripe is Tracker.find_stripe and cls._track is Tracker._track:
            raise TypeError(f"Can't instantiate {cls.__name__}: it must override find_stripe(image, background)")
        return super().__new__(cls)

    @classmethod
    def _param_names(cls) -> list[str]:
        if cls.__init__ is object.__init__:  # no parameters declared
            return []
        sig = inspect.signature(cls.__init__)
        names = []
        for p in sig.parameters.values():
            if p.name == "self":
                continue
            if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                raise TypeError(f"{cls.__name__}.__init__ must take explicit keyword parameters, not *{p.name}")
            names.append(p.name)
        return names

    def get_params(self) -> dict[str, Any]:
        """The constructor parameters and their current values."""
        return {n: getattr(self, n) for n in self._param_names()}

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.get_params().items())
        return f"{type(self).__name__}({args})"

    def track(self, image, *, background=None, colour=None) -> Track:
        """Find the stripe in one frame.

        Parameters
        ----------
        image : array_like, shape (H, W)
            Real 2-D frame in camera units (uint8 DN or float), stripe roughly
            vertical (one crossing per row). Never modified.
        background : array_like, shape (H, W), optional
            A laser-off frame of the same scene; a tracker may use or ignore it.
        colour : array_like, shape (H, W), optional
            Where the frame comes from a colour photograph: per pixel, the share
            of its light over its row that has the laser's colour, in [0, 1]
            (:func:`trackers.colour_evidence`; NaN: none). Passed, when
            given, to :meth:`find_stripe` of trackers whose ``uses_colour`` is
            True (``find_stripe(image, background, colour)``); others never
            see it, and without it every tracker gets ``find_stripe(image,
            background)``.

        Returns
        -------
        Track
        """
        img = check_image(image)
        bg = check_background(background, img.shape)
        evidence = check_colour(colour, img.shape)
        self._validate_params()
        # the evidence only where there is some and the find_stripe called takes it: a subclass that overrides the
        # hook with two arguments (image, background) still runs, without the evidence
        if evidence is not None and _takes_colour(type(self)):
            track = self.find_stripe(img, bg, evidence)
        else:
            track = self.find_stripe(img, bg)
        if track.columns.shape != (img.shape[0],):
            raise RuntimeError(
                f"{type(self).__name__} returned {track.columns.shape[0]} rows for an image of {img.shape[0]}"
            )
        return track

    def validate_params(self) -> None:
        """Raise ``ValueError`` naming a bad parameter and echoing its value; called by
        :meth:`track` before :meth:`find_stripe`.

        The default checks every parameter against :attr:`parameter_constraints`.
        Override it (calling ``super().validate_params()``) for rules that tie
        parameters together."""
        for name, constraint in type(self).parameter_constraints.items():
            constraint.check(name, getattr(self, name))

    def _validate_params(self) -> None:
        """The older name of :meth:`validate_params` (trackers written before it override this)."""
        self.validate_params()

    def find_stripe(self, image: np.ndarray, background: np.ndarray | None) -> Track:
        """Find the stripe in an already validated frame: the method a tracker overrides.

        :meth:`track` checks the frame and the parameters, calls this, and
        checks that the result has one entry per image row.

        Parameters
        ----------
        image : ndarray, shape (H, W)
            A 2-D ``uint8`` or ``float64`` frame (never modify it).
        background : ndarray, shape (H, W), or None
            The laser-off frame, same dtype rules, or None.

        Returns
        -------
        Track
            Columns and scores of length H (NaN where no stripe).

        The default calls ``self._track(image, background)`` (the older name of this hook).
        """
        return self._track(image, background)

    def _track(self, image: np.ndarray, background: np.ndarray | None) -> Track:
        raise NotImplementedError(f"{type(self).__name__} must override find_stripe(image, background)")
