"""``stripebench trackers`` and ``stripebench scenes``: what is registered."""

from __future__ import annotations

import json

from bench.cli.common import Command
from bench.cli.options import plain

__all__ = ["COMMANDS", "tracker_table"]


def tracker_table() -> list[dict]:
    """Every registered tracker: name, class, module, sub-pixel claim, summary,
    parameters with their defaults."""
    import inspect

    import trackers

    out = []
    for name in trackers.available():
        t = trackers.make(name)
        cls = type(t)
        sig = inspect.signature(cls.__init__) if cls.__init__ is not object.__init__ else None
        params = {}
        for k, v in t.get_params().items():
            default = sig.parameters[k].default if sig is not None and k in sig.parameters else v
            params[k] = None if default is inspect.Parameter.empty else default
        doc = plain((cls.__doc__ or "").strip()).splitlines()
        out.append({"name": name, "class": cls.__qualname__, "module": cls.__module__, "subpixel": bool(t.subpixel),
                    "summary": doc[0] if doc else "", "params": params})
    return out


def _add_trackers(p) -> None:
    p.add_argument("--json", action="store_true", help="print the list as JSON (parameters and defaults)")


def _trackers(args) -> int:
    table = tracker_table()
    if args.json:
        print(json.dumps(table, indent=1, default=repr))
        return 0
    for t in table:
        params = ", ".join(f"{k}={v!r}" for k, v in t["params"].items())
        print(f"{t['name']:<14} {'sub-pixel' if t['subpixel'] else 'whole-pixel':<12} {t['summary']}")
        if params:
            print(f"{'':<27}params: {params}")
    return 0


def _scenes(args) -> int:
    import scenes

    print("scenes:    " + ", ".join(scenes.available()))
    print("materials: " + ", ".join(scenes.MATERIALS))
    return 0


COMMANDS = (
    Command("trackers", "list the registered trackers with their parameters", _add_trackers, _trackers),
    Command("scenes", "list the scenes and materials", lambda p: None, _scenes),
)
