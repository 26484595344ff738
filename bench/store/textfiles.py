"""Reading text documents from disk safely: configurations (TOML), summaries and baselines (JSON), tables (CSV).

Everything stripebench reads as a document goes through :func:`read_text`
(then :func:`loads_toml` or :func:`loads_json`), so one set of bounds holds for
all of them:

* only a **regular file** is read (a FIFO, a device or a folder is refused
  without blocking: the file is opened non-blocking and checked with ``fstat``);
* at most :data:`MAX_BYTES` bytes;
* decoded as **UTF-8** (an undecodable byte is one line naming its offset);
* nesting (tables, arrays, objects) at most :data:`MAX_DEPTH` levels deep;
* integers within 64 bits (:data:`MAX_INT`; TOML's own range), so that a
  401-digit integer never reaches arithmetic that overflows.

CSV tables (manifests, references, frame lists, submissions) are parsed by
:func:`loads_csv`, as spreadsheets write them: a leading UTF-8 byte-order mark is
dropped, rows end only at LF, CRLF or CR outside quotes (a U+2028,
U+2029 or U+0085 inside a field is that field's text, not a new row), and a field
may hold up to :data:`MAX_CSV_FIELD` characters.

Every failure raises ``error`` (default :class:`bench.errors.InputError`; the
configuration reader passes :class:`bench.errors.ConfigError`, the run-folder
readers their ``RunFolderError``) with one line naming the file.
"""

from __future__ import annotations

import csv
import errno
import io
import json
import os
import stat
import tomllib
from pathlib import Path
from typing import Any

from bench.errors import InputError

__all__ = ["MAX_BYTES", "MAX_DEPTH", "MAX_INT", "read_text", "loads_json", "loads_toml", "read_json",
           "read_toml_file", "check_structure", "MAX_CSV_FIELD", "loads_csv"]

#: The largest document read, bytes (a paper run's summary.json is about 1 MB).
MAX_BYTES = 256 * 2**20
#: The deepest nesting of tables/arrays/objects accepted (stripebench's own documents use at most 8).
MAX_DEPTH = 64
#: The largest magnitude of an integer accepted (TOML's 64-bit range).
MAX_INT = 2**63 - 1
#: The longest CSV field accepted, characters (a long notes cell or a wide submission header is fine; the
#: csv module's own default is 131,072).
MAX_CSV_FIELD = 16 * 2**20

_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _kind(mode: int) -> str:
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def read_text(path, what: str = "file", *, error: type[Exception] = InputError, max_bytes: int = MAX_BYTES) -> str:
    """The UTF-8 text of the regular file at ``path``.

    Parameters
    ----------
    path : path-like
    what : str
        What the file is, for messages (``"configuration"``, ``"baseline"``).
    error : exception class
        Raised with one line on any problem.
    max_bytes : int
        Larger files are refused.

    Raises
    ------
    error
        Missing or unreadable (``cannot read WHAT 'PATH': REASON``), not a regular
        file, larger than ``max_bytes``, or not UTF-8.

    Examples
    --------
    >>> read_text("/dev/null", "configuration")
    Traceback (most recent call last):
    ...
    bench.errors.InputError: configuration '/dev/null' is not a regular file (a character device)
    """
    p = Path(path)
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        reason = "no such file" if exc.errno == errno.ENOENT else (exc.strerror or str(exc))
        raise error(f"cannot read {what} {str(p)!r}: {reason}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise error(f"{what} {str(p)!r} is not a regular file ({_kind(st.st_mode)})")
        if st.st_size > max_bytes:
            raise error(f"{what} {str(p)!r} is too large ({st.st_size} bytes; at most {max_bytes})")
        with os.fdopen(fd, "rb", closefd=True) as fh:
            fd = -1
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"cannot read {what} {str(p)!r}: {exc.strerror or exc}") from None
    finally:
        if fd >= 0:
            os.close(fd)
    if len(data) > max_bytes:
        raise error(f"{what} {str(p)!r} is too large (more than {max_bytes} bytes)")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(f"{what} {str(p)!r} is not UTF-8 text (byte {exc.start}: {data[exc.start:exc.start + 1]!r})") \
            from None


def check_structure(value: Any, where: str, *, error: type[Exception] = InputError, max_depth: int = MAX_DEPTH,
                    max_int: int = MAX_INT) -> Any:
    """``value`` unchanged if its nesting is at most ``max_depth`` deep and its integers
    within ``+-max_int`` (an iterative walk: no recursion limit is involved).

    Examples
    --------
    >>> check_structure({"a": [1, [2]]}, "x", max_depth=3)
    {'a': [1, [2]]}
    >>> check_structure({"a": [1, [2]]}, "x", max_depth=2)
    Traceback (most recent call last):
    ...
    bench.errors.InputError: x is nested too deeply (more than 2 levels of tables/arrays)
    >>> check_structure([10**30], "x")
    Traceback (most recent call last):
    ...
    bench.errors.InputError: x holds an integer of 31 digits (at most 64-bit integers: |n| <= 2**63 - 1)
    """
    stack = [(value, 0)]
    while stack:
        v, depth = stack.pop()
        if isinstance(v, (dict, list, tuple)):
            if depth >= max_depth:
                raise error(f"{where} is nested too deeply (more than {max_depth} levels of tables/arrays)")
            items = v.values() if isinstance(v, dict) else v
            stack.extend((x, depth + 1) for x in items)
        elif isinstance(v, int) and not isinstance(v, bool) and abs(v) > max_int:
            raise error(f"{where} holds an integer of {len(str(abs(v)))} digits "
                        f"(at most 64-bit integers: |n| <= 2**63 - 1)")
    return value


def _bounded_int(text: str) -> int:
    digits = text.lstrip("+-")
    if len(digits) > 19 or abs(int(text)) > MAX_INT:  # never builds a huge int
        raise _HugeInt(len(digits))
    return int(text)


class _HugeInt(Exception):
    def __init__(self, digits: int):
        self.digits = digits


def loads_json(text: str, where: str, *, error: type[Exception] = InputError, max_depth: int = MAX_DEPTH) -> Any:
    """Parse JSON text with the bounds of this module (NaN and Infinity are accepted, as Python writes them).

    Raises
    ------
    error
        ``WHERE is not valid JSON (...)``, nested too deeply, or an integer beyond 64 bits.

    Examples
    --------
    >>> loads_json('{"a": [1, 2.5, NaN]}', "doc")
    {'a': [1, 2.5, nan]}
    >>> loads_json("[" * 100000 + "]" * 100000, "doc")
    Traceback (most recent call last):
    ...
    bench.errors.InputError: doc is nested too deeply (more than 64 levels of tables/arrays)
    """
    try:
        doc = json.loads(text, parse_int=_bounded_int)
    except _HugeInt as exc:
        raise error(f"{where} holds an integer of {exc.digits} digits (at most 64-bit integers: "
                    f"|n| <= 2**63 - 1)") from None
    except RecursionError:
        raise error(f"{where} is nested too deeply (more than {max_depth} levels of tables/arrays)") from None
    except ValueError as exc:
        raise error(f"{where} is not valid JSON ({str(exc).splitlines()[0]})") from None
    return check_structure(doc, where, error=error, max_depth=max_depth)


def loads_toml(text: str, where: str, *, error: type[Exception] = InputError, max_depth: int = MAX_DEPTH) -> dict:
    """Parse TOML text with the bounds of this module.

    Raises
    ------
    error
        ``WHERE: invalid TOML: ...``, nested too deeply, or an integer beyond 64 bits.

    Examples
    --------
    >>> loads_toml("seed = 1", "c.toml")
    {'seed': 1}
    >>> loads_toml("seed = 1" + "0" * 400, "c.toml")
    Traceback (most recent call last):
    ...
    bench.errors.InputError: c.toml holds an integer of 401 digits (at most 64-bit integers: |n| <= 2**63 - 1)
    """
    try:
        doc = tomllib.loads(text)
    except RecursionError:
        raise error(f"{where} is nested too deeply (more than {max_depth} levels of tables/arrays)") from None
    except tomllib.TOMLDecodeError as exc:
        raise error(f"{where}: invalid TOML: {exc}") from None
    except ValueError as exc:  # tomllib's int() of more than 4300 digits
        raise error(f"{where}: invalid TOML: {str(exc).splitlines()[0]}") from None
    return check_structure(doc, where, error=error, max_depth=max_depth)


def read_json(path, what: str = "JSON file", *, error: type[Exception] = InputError) -> Any:
    """:func:`read_text` then :func:`loads_json` (messages name ``what`` and the path)."""
    return loads_json(read_text(path, what, error=error), f"{what} {str(Path(path))!r}", error=error)


def read_toml_file(path, what: str = "TOML file", *, error: type[Exception] = InputError) -> dict:
    """:func:`read_text` then :func:`loads_toml` (messages name the path)."""
    return loads_toml(read_text(path, what, error=error), str(Path(path)), error=error)


def loads_csv(text: str, where: str, *, error: type[Exception] = InputError, header: bool = True):
    r"""The rows of a CSV table, read as a spreadsheet writes it.

    Parameters
    ----------
    text : str
        The table (from :func:`read_text`); a leading byte-order mark is dropped.
    where : str
        The file's name, for messages.
    error : exception class
        Raised with one line naming ``where`` (a field longer than :data:`MAX_CSV_FIELD`, or
        text the csv module cannot parse, such as a quote left open).
    header : bool
        True: a list of dicts keyed by the first row (``csv.DictReader``); the header is the
        dicts' keys, also returned. False: a list of lists.

    Returns
    -------
    (fieldnames, rows) if ``header`` else rows

    Examples
    --------
    >>> loads_csv('\ufeffname,notes\r\na,"one\u2028two"\r\n', "manifest.csv")
    (['name', 'notes'], [{'name': 'a', 'notes': 'one\u2028two'}])
    """
    if text.startswith("\ufeff"):
        text = text[1:]
    if csv.field_size_limit() != MAX_CSV_FIELD:  # the csv module's limit is process-wide: set, never restored,
        csv.field_size_limit(MAX_CSV_FIELD)    # so that a reader in another thread never sees it shrink
    try:
        stream = io.StringIO(text, newline="")
        if header:
            reader = csv.DictReader(stream)
            rows = list(reader)
            return list(reader.fieldnames or []), rows
        return list(csv.reader(stream))
    except csv.Error as exc:
        msg = str(exc)
        if "field larger than field limit" in msg:
            msg = f"a field is longer than {MAX_CSV_FIELD:,} characters"
        raise error(f"{where}: not a readable CSV table ({msg})") from None
