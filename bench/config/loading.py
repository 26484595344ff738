"""Reading configurations: TOML files, the embedded profiles, and copies with fields replaced.

Every reader validates with :func:`bench.config.schema.parse`; a file is read by
:func:`read_toml` (a regular UTF-8 file with bounded nesting), a profile from
``bench/config/profiles/NAME.toml``.

Examples
--------
>>> PROFILES[0]
'paper'
>>> profile("fast")
Traceback (most recent call last):
...
bench.errors.ConfigError: unknown profile 'fast'; available: paper, quick, ci, marble, field
"""

from __future__ import annotations

import copy
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from bench.config.schema import Config, parse
from bench.errors import ConfigError

__all__ = ["PROFILES", "read_toml", "load", "profile", "with_overrides"]

#: The embedded profiles (``bench/config/profiles/NAME.toml``), the default ``paper`` first.
PROFILES = ("paper", "quick", "ci", "marble", "field")


def read_toml(path, what: str = "configuration") -> dict[str, Any]:
    """The TOML document at ``path`` as a dict.

    Only a regular file is read, as UTF-8, at most
    :data:`bench.store.textfiles.MAX_DEPTH` levels deep with 64-bit integers
    (:mod:`bench.store.textfiles`).

    Raises
    ------
    ConfigError
        Missing, unreadable, not a regular file (a FIFO is refused without
        waiting), not UTF-8, invalid TOML, nested too deeply, a huge integer.
    """
    from bench.store.textfiles import read_toml_file

    return read_toml_file(path, what, error=ConfigError)


def load(path) -> Config:
    """Read and validate a TOML configuration file."""
    return parse(read_toml(path), source=str(Path(path)))


def profile(name: str) -> Config:
    """One of the embedded profiles (:data:`PROFILES`): ``paper`` (the default experiment), ``quick``, ``ci``, ..."""
    if not isinstance(name, str) or name not in PROFILES:
        raise ConfigError(f"unknown profile {name!r}; available: {', '.join(PROFILES)}")
    text = resources.files("bench.config.profiles").joinpath(f"{name}.toml").read_text(encoding="utf-8")
    return parse(tomllib.loads(text), source=f"profile:{name}")


def with_overrides(config: Config, **changes) -> Config:
    """A copy with top-level fields replaced (e.g. ``seed``, ``trackers``), re-validated."""
    d = copy.deepcopy(config.to_dict())
    d.update({k: (list(v) if isinstance(v, tuple) else v) for k, v in changes.items()})
    return parse(d, source=config.source)
