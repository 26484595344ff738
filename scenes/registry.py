"""``available()`` and ``make()``: the scene catalogue's front door."""

from __future__ import annotations

from typing import List

from . import objects
from .params import validate
from .scene import Scene

__all__ = ["available", "make"]


def available() -> List[str]:
    """Sorted names of the scenes (objects) that :func:`make` builds."""
    return sorted(objects.OBJECTS)


def make(name: str, **params) -> Scene:
    """Build a scene; every parameter has a default (see :data:`scenes.params.DEFAULTS`).

    Raises
    ------
    KeyError
        Unknown scene name, ``material`` or ``ambient_illuminant`` (lists the valid ones).
    TypeError
        Unknown parameter name (lists the valid ones).
    ValueError
        Invalid value (names the parameter, echoes the value).
    """
    if name not in objects.OBJECTS:
        raise KeyError(f"unknown scene {name!r}; valid: {', '.join(available())}")
    scene = Scene(name, validate(params))
    _ = scene.object  # builds the geometry: a wall through the object is a ValueError here
    return scene
