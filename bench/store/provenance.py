"""Provenance: what made a result (package versions, the git revision, fingerprints of the source).

Every run kind (``run``, ``real``, ``sweep``) records these in its summary;
checkpoints and sweep units record :func:`code_fingerprint` /
:func:`source_fingerprint` so that results made by other code are not resumed.
"""

from __future__ import annotations

import platform
import subprocess
import sys
from importlib import metadata
from pathlib import Path

__all__ = ["versions", "git_revision", "machine", "source_fingerprint", "tracker_source_files", "code_fingerprint"]


def versions() -> dict[str, str]:
    """The versions of Python and of the packages that shape results (``not installed`` where absent)."""
    out = {"python": platform.python_version()}
    for dist in ("stripebench", "numpy", "numba", "scikit-image", "mitsuba", "drjit", "pandas", "matplotlib",
                 "pyvista", "colour-science"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    return out


def git_revision() -> str:
    """``git describe --always --dirty`` of the source tree, or ``unknown``."""
    root = Path(__file__).resolve().parents[2]
    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=12"], cwd=root,
                             capture_output=True, text=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def machine() -> dict:
    """The machine a result was made on: ``cpu`` (the model name of ``/proc/cpuinfo``, else
    ``platform.processor()``, else ``unknown``), ``cores`` (the CPU cores this process may use),
    ``system`` and ``arch`` (``platform.system()``, ``platform.machine()``).

    Examples
    --------
    >>> sorted(machine())
    ['arch', 'cores', 'cpu', 'system']
    """
    import os

    cpu = ""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            for line in fh:
                if line.lower().startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return {"cpu": cpu or platform.processor() or "unknown", "cores": cores, "system": platform.system(),
            "arch": platform.machine()}


def source_fingerprint(packages=("trackers", "scenes")) -> str:
    """A hash of the source (``.py`` files) of the named packages, by default those whose code changes results
    (``trackers``, ``scenes``): a checkpoint made by other code is not resumed. ``("bench", "trackers",
    "scenes")`` fingerprints the whole of what a study runs (``predictcheck``'s runs record it, so that two runs made
    by the same code are not compared as two versions).

    Examples
    --------
    >>> a = source_fingerprint()
    >>> whole = source_fingerprint(("bench", "trackers", "scenes"))
    >>> len(a), a == source_fingerprint(("trackers", "scenes")), a == whole
    (16, True, False)
    """
    import hashlib
    import importlib

    h = hashlib.sha256()
    for name in packages:
        root = Path(importlib.import_module(name).__file__).parent
        for f in sorted(root.rglob("*.py")):
            h.update(str(f.relative_to(root)).encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


def tracker_source_files(trackers_) -> list[Path]:
    """The source files behind tracker objects, wherever their classes live.

    For every class in each tracker's MRO (the library's own ``trackers``
    package excepted, :func:`source_fingerprint` covers it): the ``.py`` files
    of its top-level package, or its module file when it is a plain module.
    Entry-point plugins are included, so editing a plugin invalidates its results.
    """
    seen: set[Path] = set()
    for t in trackers_:
        t = getattr(t, "wrapped", t)  # a timed or isolated tracker: the tracker it runs
        for cls in type(t).__mro__:
            top = cls.__module__.split(".")[0]
            if top in ("builtins", "abc", "trackers"):
                continue
            mod = sys.modules.get(top)
            if mod is None:
                continue
            paths = getattr(mod, "__path__", None)
            if paths is not None:
                for root in paths:
                    seen.update(Path(root).rglob("*.py"))
            elif getattr(mod, "__file__", None):
                seen.add(Path(mod.__file__))
    return sorted(p.resolve() for p in seen if p.is_file())


def code_fingerprint(trackers_=()) -> str:
    """:func:`source_fingerprint` plus the source of the given trackers' own modules (plugins)."""
    import hashlib

    h = hashlib.sha256(source_fingerprint().encode())
    for f in tracker_source_files(trackers_):
        h.update(str(f).encode())
        h.update(f.read_bytes())
    return h.hexdigest()[:16]
