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

__all__ = ["StripebenchError", "ConfigError", "InputError", "QUOTE_CHARS", "LINE_CHARS", "quoted", "one_line"]

#: The most characters of one value an error line quotes (a longer one is cut, its length said).
QUOTE_CHARS = 80
#: The longest error line printed (a message that quotes a whole file is cut to this).
LINE_CHARS = 2000


class StripebenchError(Exception):
    """An expected failure: ``str(err)`` is one line for the user (exit status 2 on the command line)."""


class ConfigError(StripebenchError, ValueError):
    """A configuration, profile, sweep table or option value that breaks the schema (:mod:`bench.config`)."""


class InputError(StripebenchError, ValueError):
    """A file that cannot be read as what it should be: not a regular file, not UTF-8, too large,
    nested too deeply, not valid JSON/TOML (:mod:`bench.store.textfiles`)."""


def _cut(text: str, limit: int) -> str:
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def quoted(value, limit: int = QUOTE_CHARS) -> str:
    """``repr(value)`` for an error line, at most about ``limit`` characters of it: what a user gave
    (a field, a name, an option's value) may be megabytes long.

    Examples
    --------
    >>> quoted("frame-1")
    "'frame-1'"
    >>> quoted("x" * 10_000_000, limit=5)
    "'xxxxx'... (10000000 characters)"
    """
    if isinstance(value, str):
        return repr(value) if len(value) <= limit else f"{value[:limit]!r}... ({len(value)} characters)"
    return _cut(repr(value), limit)


def one_line(text, limit: int = LINE_CHARS) -> str:
    """``text`` as one line of at most about ``limit`` characters (line breaks become spaces): every error
    line the command line prints goes through this.

    Examples
    --------
    >>> one_line("first\\nsecond")
    'first second'
    >>> one_line("y" * 50, limit=10)
    'yyyyyyyyyy... (50 characters)'
    """
    return _cut(" ".join(str(text).splitlines()), limit)
