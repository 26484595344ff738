"""Name -> tracker factory registry, with entry-point plugins."""

from __future__ import annotations

import importlib
import warnings
from importlib.metadata import entry_points
from typing import Callable

from ._base import Tracker

__all__ = ["Registry", "ENTRY_POINT_GROUP"]

ENTRY_POINT_GROUP = "stripebench.trackers"


def _lazy(target: str) -> Callable[..., Tracker]:
    """A factory that imports ``'module:attr'`` on first use."""

    def factory(**params):
        module, _, attr = target.partition(":")
        return getattr(importlib.import_module(module), attr)(**params)

    factory.__qualname__ = f"lazy({target})"
    return factory


class Registry:
    """Registered tracker factories.

    Built-in trackers are registered at import time by name and import path (so
    ``import trackers`` imports no tracker module). Third-party trackers are
    found through the entry-point group ``stripebench.trackers`` the first time
    the registry is queried; each entry point names a :class:`Tracker`
    subclass whose ``name`` equals the entry-point name. A broken entry point
    gives a ``RuntimeWarning`` naming it and is skipped.
    """

    def __init__(self, group: str = ENTRY_POINT_GROUP):
        self.group = group
        self._factories: dict[str, Callable[..., Tracker]] = {}
        self._plugins_loaded = False
        self._unlisted: set[str] = set()

    def register(self, name: str, factory=None, *, listed: bool = True):
        """Register ``factory`` (a class, callable or ``'module:attr'``) under ``name``.

        Usable as a decorator: ``@registry.register("mine")``. ``listed=False``:
        made by :meth:`make` but left out of :meth:`available`'s default list (a
        tracker that cannot run without parameters, such as ``external``).

        Raises
        ------
        ValueError
            If ``name`` is empty or already registered.
        """
        if not isinstance(name, str) or not name:
            raise ValueError(f"`name` must be a non-empty string, got {name!r}")

        def add(f):
            if name in self._factories:
                raise ValueError(f"a tracker named {name!r} is already registered")
            self._factories[name] = _lazy(f) if isinstance(f, str) else f
            if not listed:
                self._unlisted.add(name)
            return f

        return add if factory is None else add(factory)

    def unregister(self, name: str):
        """Remove ``name`` and return its factory (for tests and notebooks that swap a tracker).

        Raises
        ------
        KeyError
            If no tracker has that name.
        """
        self._load_plugins()
        try:
            factory = self._factories.pop(name)
        except (KeyError, TypeError):
            raise KeyError(f"no tracker named {name!r} is registered") from None
        self._unlisted.discard(name)
        return factory

    def _load_plugins(self) -> None:
        if self._plugins_loaded:
            return
        self._plugins_loaded = True
        for ep in entry_points(group=self.group):
            where = f"entry point {ep.name!r} ({ep.value}) in group {self.group!r}"
            if ep.name in self._factories:
                warnings.warn(f"ignoring tracker {where}: the name is already registered", RuntimeWarning, stacklevel=3)
                continue
            try:
                obj = ep.load()
            except Exception as exc:  # a plugin must not break the others
                warnings.warn(
                    f"could not load tracker {where}: {type(exc).__name__}: {exc}", RuntimeWarning, stacklevel=3
                )
                continue
            if not (isinstance(obj, type) and issubclass(obj, Tracker)):
                warnings.warn(f"ignoring tracker {where}: {obj!r} is not a Tracker subclass", RuntimeWarning, stacklevel=3)
                continue
            if obj.name != ep.name:
                warnings.warn(
                    f"ignoring tracker {where}: its class declares name={obj.name!r}", RuntimeWarning, stacklevel=3
                )
                continue
            self._factories[ep.name] = obj

    def available(self, *, unlisted: bool = False) -> list[str]:
        """Sorted names of every registered tracker (with ``unlisted``, also those registered ``listed=False``)."""
        self._load_plugins()
        return sorted(n for n in self._factories if unlisted or n not in self._unlisted)

    def make(self, name: str, **params) -> Tracker:
        """A new tracker ``name`` built with ``params``.

        Raises
        ------
        KeyError
            If no tracker has that name (the message lists the available ones).
        """
        self._load_plugins()
        try:
            factory = self._factories[name]
        except (KeyError, TypeError):
            raise KeyError(f"unknown tracker {name!r}; available: {', '.join(sorted(self._factories))}") from None
        tracker = factory(**params)
        if not isinstance(tracker, Tracker):
            raise TypeError(f"factory of tracker {name!r} returned {type(tracker).__name__}, not a Tracker")
        return tracker
