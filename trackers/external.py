"""``external``: a tracker that is another program (C++, CUDA, MATLAB, a ROS node's core, a script).

The frame is written to a temporary file, the program runs, its CSV answer is
read back. Two modes:

``mode = "per-frame"`` (default)
    ``command`` is run once per frame, its placeholders ``{image}``,
    ``{background}`` and ``{out}`` replaced by the paths of the frame, the
    laser-off frame (an empty string when there is none) and the CSV file the
    program must write.
``mode = "persistent"``
    ``command`` (no placeholders) is started once and kept running. For each
    frame it reads one line on stdin: the image path, then a tab and the
    background path when there is one; it answers on stdout with the frame's
    CSV lines followed by a line ``end``. Much faster when the program has a
    long start (MATLAB, a JIT, a GPU context).

The answer is CSV ``row,col[,score]`` (an optional header line ``row,col...``;
rows left out mean no stripe there; ``col`` in px with pixel centres at
integers). Frames are written as 8-bit PNG (``image_format = "png"``) or
binary PGM (``"pgm"``, trivial to read in C) when they are uint8, and as NumPy
``.npy`` (float64) otherwise, so the program sees exactly the tracker's input.
A program that fails (non-zero exit status), exceeds ``timeout_s`` on a frame
(it is killed) or answers something malformed raises ``RuntimeError``,
``TimeoutError`` or ``ValueError``; the harness records that frame as failed.

This module imports only the standard library and NumPy.
"""

from __future__ import annotations

import contextlib
import os
import select
import shutil
import struct
import subprocess
import tempfile
import time
import zlib

import numpy as np

from ._base import Track, Tracker
from ._params import Choice, Real, StrList
from .processes import kill_group, popen_group

__all__ = ["ExternalTracker", "png_bytes", "parse_answer"]

MODES = ("per-frame", "persistent")
FORMATS = ("png", "pgm")


def png_bytes(image: np.ndarray) -> bytes:
    """A minimal 8-bit grey PNG of ``image`` (H, W) uint8 (no dependency beyond zlib).

    >>> png_bytes(np.zeros((1, 1), np.uint8))[:8]
    b'\\x89PNG\\r\\n\\x1a\\n'
    """
    h, w = image.shape
    raw = b"".join(b"\x00" + image[r].tobytes() for r in range(h))

    def chunk(tag: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def parse_answer(text: str, height: int) -> Track:
    """A program's CSV answer (``row,col[,score]`` lines) as a :class:`Track` of ``height`` rows.

    Raises
    ------
    ValueError
        A line that is not ``row,col[,score]`` numbers, a row outside [0, height), a repeated row,
        a non-finite column or score (naming the line).

    Examples
    --------
    >>> parse_answer("row,col\\n1,2.5\\n", 3).columns.tolist()
    [nan, 2.5, nan]
    """
    cols = np.full(height, np.nan)
    score = np.full(height, np.nan)
    for n, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or (n == 1 and line.lower().startswith("row")):
            continue
        parts = [p.strip() for p in line.split(",")]
        try:
            if len(parts) not in (2, 3):
                raise ValueError
            row = int(parts[0])
            if not parts[1]:
                continue  # an empty col: no stripe on that row
            col = float(parts[1])
            sc = float(parts[2]) if len(parts) == 3 and parts[2] else 1.0
        except ValueError:
            raise ValueError(f"answer line {n} is not row,col[,score] numbers: {line[:80]!r}") from None
        if not 0 <= row < height:
            raise ValueError(f"answer line {n}: row {row} outside [0, {height})")
        if not (np.isfinite(col) and np.isfinite(sc)):
            raise ValueError(f"answer line {n}: col and score must be finite, got {line[:80]!r}")
        if not np.isnan(cols[row]):
            raise ValueError(f"answer line {n}: row {row} given twice")
        cols[row], score[row] = col, sc
    return Track(cols, score)


class ExternalTracker(Tracker):
    """Another program as a tracker: frames to files, the program's CSV back.

    Parameters
    ----------
    command : list of str
        The program and its arguments. ``per-frame``: ``{image}``, ``{background}``
        and ``{out}`` are replaced in each argument; ``persistent``: no placeholders.
    mode : str, default "per-frame"
        ``"per-frame"`` or ``"persistent"`` (see the module docstring).
    image_format : str, default "png"
        How uint8 frames are written: ``"png"`` or ``"pgm"`` (float frames are always ``.npy``).
    timeout_s : float or None, default 30.0
        Seconds the program may take per frame (it is killed beyond); None: no limit.

    Notes
    -----
    ``score`` is the program's third column, 1.0 on rows where it gives none.
    Call :meth:`close` to stop a persistent program and remove the temporary
    folder (also done when the tracker is garbage-collected).

    Examples
    --------
    >>> import sys
    >>> t = ExternalTracker([sys.executable, "-c", "open(r'{out}', 'w').write('0,2\\\\n')"])
    >>> t.track(np.zeros((2, 4), np.uint8)).columns.tolist()
    [2.0, nan]
    >>> t.close()
    """

    name = "external"
    subpixel = True  # whatever the program claims; the conformance suite does not run it

    def __init__(self, command=None, mode="per-frame", image_format="png", timeout_s=30.0):
        self.command = command
        self.mode = mode
        self.image_format = image_format
        self.timeout_s = timeout_s

    parameter_constraints = {"command": StrList(), "mode": Choice(frozenset(MODES)),
                             "image_format": Choice(frozenset(FORMATS)),
                             "timeout_s": Real(low=0, low_open=True, optional=True)}

    def validate_params(self) -> None:
        """The parameters' constraints, then: a persistent program's command takes no placeholders."""
        super().validate_params()
        c = self.command
        if self.mode == "persistent" and any(p in a for a in c for p in ("{image}", "{background}", "{out}")):
            raise ValueError(f"`command` of a persistent program takes no placeholders, got {list(c)!r}")

    # -- files -----------------------------------------------------------------
    def _tmp(self) -> str:
        d = self.__dict__.get("_dir")
        if d is None or not os.path.isdir(d):
            d = tempfile.mkdtemp(prefix="stripebench-external-")
            self.__dict__["_dir"] = d
        return d

    def _write(self, arr: np.ndarray, stem: str) -> str:
        d = self._tmp()
        if arr.dtype == np.uint8 and self.image_format == "png":
            path = os.path.join(d, stem + ".png")
            data = png_bytes(arr)
        elif arr.dtype == np.uint8:
            path = os.path.join(d, stem + ".pgm")
            data = f"P5\n{arr.shape[1]} {arr.shape[0]}\n255\n".encode() + arr.tobytes()
        else:
            path = os.path.join(d, stem + ".npy")
            with open(path, "wb") as fh:
                np.save(fh, np.asarray(arr, np.float64))
            return path
        with open(path, "wb") as fh:
            fh.write(data)
        return path

    # -- running ---------------------------------------------------------------
    def find_stripe(self, image, background):
        img = self._write(image, "frame")
        bg = "" if background is None else self._write(background, "frame_off")
        if self.mode == "persistent":
            return parse_answer(self._ask(img, bg), image.shape[0])
        out = os.path.join(self._tmp(), "answer.csv")
        with contextlib.suppress(FileNotFoundError):
            os.remove(out)
        args = [a.replace("{image}", img).replace("{background}", bg).replace("{out}", out) for a in self.command]
        try:  # its own process group: a timeout kills it and every process it started
            proc = popen_group(args, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        except OSError as exc:
            raise RuntimeError(f"cannot run {self.command[0]!r}: {exc.strerror or exc}") from None
        try:
            _, stderr = proc.communicate(timeout=self.timeout_s)
        except subprocess.TimeoutExpired:
            kill_group(proc)
            proc.communicate()
            raise TimeoutError(f"{self.command[0]} took longer than timeout_s = {self.timeout_s:g} s "
                               "(killed, with every process it started)") from None
        except BaseException:
            kill_group(proc)
            raise
        if proc.returncode != 0:
            raise RuntimeError(f"{self.command[0]} exited with status {proc.returncode}: {_last_line(stderr)}")
        try:
            with open(out, encoding="utf-8") as fh:
                text = fh.read()
        except FileNotFoundError:
            raise RuntimeError(f"{self.command[0]} wrote no answer to {{out}}") from None
        return parse_answer(text, image.shape[0])

    def _ask(self, img: str, bg: str) -> str:
        proc = self.__dict__.get("_proc")
        if proc is None or proc.poll() is not None:
            try:
                proc = popen_group(list(self.command), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   stderr=subprocess.DEVNULL, bufsize=0)
            except OSError as exc:
                raise RuntimeError(f"cannot run {self.command[0]!r}: {exc.strerror or exc}") from None
            self.__dict__["_proc"] = proc
            self.__dict__["_buf"] = b""
        try:
            proc.stdin.write((img + ("\t" + bg if bg else "") + "\n").encode())
            proc.stdin.flush()
        except (BrokenPipeError, OSError):
            self._stop()
            raise RuntimeError(f"{self.command[0]} exited before reading the frame") from None
        deadline = None if self.timeout_s is None else time.monotonic() + self.timeout_s
        buf = self.__dict__["_buf"]
        fd = proc.stdout.fileno()
        while b"\nend\n" not in b"\n" + buf:
            wait = None if deadline is None else deadline - time.monotonic()
            if wait is not None and wait <= 0:
                self._stop()
                raise TimeoutError(f"{self.command[0]} took longer than timeout_s = {self.timeout_s:g} s "
                                   "(killed)")
            ready, _, _ = select.select([fd], [], [], wait)
            if not ready:
                continue
            chunk = os.read(fd, 65536)
            if not chunk:
                code = proc.wait()
                self._stop()
                raise RuntimeError(f"{self.command[0]} exited (status {code}) before answering the frame")
            buf += chunk
        text = (b"\n" + buf).split(b"\nend\n", 1)
        self.__dict__["_buf"] = text[1]
        return text[0].decode("utf-8", "replace")

    def _stop(self) -> None:
        proc = self.__dict__.pop("_proc", None)
        if proc is not None:
            with contextlib.suppress(OSError):
                proc.stdin.close()
            if proc.poll() is None:
                try:
                    proc.wait(timeout=1.0)
                except subprocess.TimeoutExpired:
                    pass
            kill_group(proc)  # and whatever it left running
            with contextlib.suppress(OSError):
                proc.stdout.close()

    def close(self) -> None:
        """Stop a persistent program and remove the temporary folder."""
        self._stop()
        d = self.__dict__.pop("_dir", None)
        if d is not None:
            shutil.rmtree(d, ignore_errors=True)

    def __del__(self):
        with contextlib.suppress(Exception):
            self.close()


def _last_line(stderr: bytes) -> str:
    lines = [ln for ln in stderr.decode("utf-8", "replace").splitlines() if ln.strip()]
    return lines[-1][:160] if lines else "(nothing on stderr)"
