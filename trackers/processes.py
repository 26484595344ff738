"""Child processes that never outlive their parent.

Used by :class:`trackers.external.ExternalTracker` (a program and everything it starts
run in a process group of their own, killed as a group on a timeout) and by the
harness's worker pools (a figure or tracking worker dies with the process that
started it, whatever signal ends that process).

Linux only where noted: elsewhere :func:`die_with_parent` does nothing.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import signal
import subprocess
import sys

__all__ = ["die_with_parent", "popen_group", "kill_group"]

_PR_SET_PDEATHSIG = 1
try:  # resolved here, in the parent, so that a forked child only calls it
    _prctl = ctypes.CDLL(None, use_errno=True).prctl if sys.platform.startswith("linux") else None
except (OSError, AttributeError):  # pragma: no cover - a libc without prctl
    _prctl = None


def die_with_parent(parent_pid: int | None = None) -> None:
    """Ask the kernel to SIGKILL this process when the thread that started it exits
    (``prctl(PR_SET_PDEATHSIG)``, Linux); exit at once if ``parent_pid`` is given and
    that parent is already gone. Safe as a ``preexec_fn`` or a pool's ``initializer``."""
    if _prctl is not None:
        _prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if parent_pid is not None and os.getppid() != parent_pid:
        os._exit(1)


def popen_group(args, **kwargs) -> subprocess.Popen:
    """:class:`subprocess.Popen` of ``args`` in a new session (its own process group, so
    :func:`kill_group` reaches every process it starts), killed by the kernel if this
    process dies first (the direct child; its own children are reached by
    :func:`kill_group` only)."""
    return subprocess.Popen(args, start_new_session=True, preexec_fn=die_with_parent, **kwargs)


def kill_group(proc: subprocess.Popen) -> None:
    """SIGKILL ``proc``'s process group (every process it started that did not leave it)
    and reap ``proc``."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(proc.pid, signal.SIGKILL)
    with contextlib.suppress(ProcessLookupError):
        proc.kill()
    proc.wait()
