"""The one exception base of stripebench's expected failures.

Every problem the user can fix (a bad configuration, an unreadable file, a
run folder in use, a real set that breaks its layout, an unreachable
scheduler) raises a subclass of :class:`StripebenchError` whose ``str()`` is
one line naming the argument, key or file and echoing the value.  The command
line (:func:`bench.cli.main`) catches this base once and prints
``stripebench: error: <message>`` with exit status 2.

This module is the lowest layer of :mod:`bench` (it imports nothing), so every
layer can raise its own subclass: :class:`ConfigError` (``bench.config``),
``RunFolderError`` (``bench.store.runfolder``), ``ImageError`` and
``DatasetError`` (``bench.store.realset``), ``SweepError`` (``bench.run.sweep``),
``UsageError`` (``bench.cli``).

Examples
--------
>>> issubclass(ConfigError, StripebenchError) and issubclass(ConfigError, ValueError)
True
>>> str(ConfigError("`seed` must be an integer >= 0, got -1"))
'`seed` must be an integer >= 0, got -1'
"""

from __future__ import annotations

__all__ = ["StripebenchError", "ConfigError", "InputError"]


class StripebenchError(Exception):
    """An expected failure: ``str(err)`` is one line for the user (exit status 2 on the command line)."""


class ConfigError(StripebenchError, ValueError):
    """A configuration, profile, sweep table or option value that breaks the schema (:mod:`bench.config`)."""


class InputError(StripebenchError, ValueError):
    """A file that cannot be read as what it should be: not a regular file, not UTF-8, too large,
    nested too deeply, not valid JSON/TOML (:mod:`bench.store.textfiles`)."""
