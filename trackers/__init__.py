"""Laser-stripe trackers: one interface, a registry and the built-in trackers.

>>> import trackers
>>> {"threshold", "centroid", "dp4", "dp8", "dp8_subpixel", "dp_gap", "steger"} <= set(trackers.available())
True
>>> t = trackers.make("dp8")
>>> t.name
'dp8'

Importing this package imports no tracker module, Mitsuba, matplotlib or
pyvista; built-in trackers are imported when first made, third-party ones
(entry-point group ``stripebench.trackers``) when the registry is first asked.
"""

from ._base import Track, Tracker
from ._params import Bool, Choice, Int, Real, StrList
from ._registry import ENTRY_POINT_GROUP, Registry
from ._stripe import StripeAnswer, StripeTest, ask, colour_evidence

__all__ = ["Track", "Tracker", "available", "make", "register", "unregister", "ENTRY_POINT_GROUP",
           "Real", "Int", "Choice", "Bool", "StrList", "StripeTest", "StripeAnswer", "ask", "colour_evidence"]

_REGISTRY = Registry(ENTRY_POINT_GROUP)
for _name, _target in {
    "threshold": "trackers.threshold:ThresholdTracker",
    "centroid": "trackers.centroid:CentroidTracker",
    "dp4": "trackers.dp:DP4Tracker",
    "dp8": "trackers.dp:DP8Tracker",
    "gauss3": "trackers.gauss3:Gauss3Tracker",
    "parabolic": "trackers.parabolic:ParabolicTracker",
    "blais_rioux": "trackers.blais_rioux:BlaisRiouxTracker",
    "com_bg": "trackers.com_bg:ComBgTracker",
    "steger": "trackers.steger:StegerTracker",
    "dp8_subpixel": "trackers.dp_subpixel:DP8SubpixelTracker",
    "dp_gap": "trackers.dp_gap:DPGapTracker",
}.items():
    _REGISTRY.register(_name, _target)
del _name, _target
# another program as a tracker: it needs its `command`, so it is not in the default list
_REGISTRY.register("external", "trackers.external:ExternalTracker", listed=False)
# the network trained on renders (trackers/models/learned.npz): unlisted (the `field` profile names it), so that
# `trackers = []` (every listed tracker) keeps its results
_REGISTRY.register("learned", "trackers.learned:LearnedTracker", listed=False)


def available(*, unlisted: bool = False) -> list[str]:
    """Sorted names of the registered trackers (built-in and plugins) that run with their defaults;
    ``unlisted=True`` adds those that need parameters first (``external``: another program)."""
    return _REGISTRY.available(unlisted=unlisted)


def make(name: str, **params) -> Tracker:
    """A new tracker: ``make("dp8", eps=2.0)``.

    Raises
    ------
    KeyError
        For an unknown name; the message lists the available ones.
    """
    return _REGISTRY.make(name, **params)


def register(name: str, factory=None):
    """Register a tracker factory (class, callable or ``'module:attr'``) under
    ``name``; usable as a decorator. Raises ``ValueError`` if the name is taken."""
    return _REGISTRY.register(name, factory)


def unregister(name: str):
    """Remove the tracker ``name`` and return its factory (tests and notebooks swap trackers
    with it). Raises ``KeyError`` if no tracker has that name."""
    return _REGISTRY.unregister(name)
