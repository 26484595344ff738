"""Choosing and loading the Mitsuba variant safely.

Order of preference: ``cuda_ad_mono`` (a working GPU), ``llvm_ad_mono`` (a working
LLVM), ``scalar_rgb`` (always works; no ``scalar_mono`` exists, so scenes use
equal RGB values and one channel is read back).  ``STRIPEBENCH_VARIANT``
overrides the choice.

A broken LLVM (Debian's 14/15/16 with drjit 1.5) *aborts the whole process*
inside the JIT, so each candidate is first tried in a child process that
renders a tiny scene; only a variant that survived there is set in this process.
Before drjit is imported, ``DRJIT_LIBLLVM_PATH`` is pointed at a
``libLLVM.so.19*``/``libLLVM-19.so`` (or newer) found in the usual library
folders, unless the variable is already set.  The choice is printed to stderr
once per process and cached for the process's lifetime (it is a property of the
machine, not of any frame).
"""

from __future__ import annotations

import glob
import os
import re
import subprocess
import sys
from typing import Optional

__all__ = ["CANDIDATES", "VariantError", "find_libllvm", "probe", "choose", "check_forced", "mitsuba", "active_variant",
           "is_mono"]

CANDIDATES = ("cuda_ad_mono", "llvm_ad_mono", "scalar_rgb")
ENV_VARIANT = "STRIPEBENCH_VARIANT"
_LLVM_DIRS = ("/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib",
              "/usr/local/lib", "/opt/homebrew/opt/llvm/lib", "/usr/local/opt/llvm/lib")
_MIN_LLVM = 17
_chosen: Optional[str] = None

_PROBE = r"""
import sys
import mitsuba as mi
mi.set_variant(sys.argv[1])
s = mi.load_dict({'type': 'scene', 'integrator': {'type': 'path', 'max_depth': 3},
    'sensor': {'type': 'perspective', 'fov': 30,
               'film': {'type': 'hdrfilm', 'width': 8, 'height': 6, 'rfilter': {'type': 'box'}},
               'sampler': {'type': 'multijitter', 'sample_count': 4}},
    'sphere': {'type': 'sphere', 'center': [0, 0, 3], 'radius': 1.0},
    'sky': {'type': 'constant', 'radiance': 1.0}}, optimize=False)
import numpy as np
img = np.array(mi.render(s))
assert np.isfinite(img).all() and img.max() > 0
print('ok')
"""


class VariantError(ValueError):
    """``$STRIPEBENCH_VARIANT`` names a variant that cannot render here; ``str(err)`` is one line."""


def find_libllvm() -> Optional[str]:
    """Path of the newest ``libLLVM`` (major >= 17) in the usual folders, or None."""
    best = None
    for d in _LLVM_DIRS + tuple(sorted(glob.glob("/usr/lib/llvm-*/lib"))):
        for path in glob.glob(os.path.join(d, "libLLVM*.so*")) + glob.glob(os.path.join(d, "libLLVM*.dylib")):
            m = re.search(r"libLLVM[-.](?:so\.)?(\d+)", os.path.basename(path))
            if m and int(m.group(1)) >= _MIN_LLVM:
                key = (int(m.group(1)), path)
                if best is None or key > best:
                    best = key
    return best[1] if best else None


def _child_env() -> dict:
    env = dict(os.environ)
    if "DRJIT_LIBLLVM_PATH" not in env:
        lib = find_libllvm()
        if lib:
            env["DRJIT_LIBLLVM_PATH"] = lib
    return env


def probe(variant: str, timeout_s: float = 180.0) -> bool:
    """True when ``variant`` renders a tiny scene in a child process (a crash there is harmless)."""
    try:
        r = subprocess.run([sys.executable, "-c", _PROBE, variant], env=_child_env(), capture_output=True,
                           text=True, timeout=timeout_s)
    except (subprocess.TimeoutExpired, OSError):
        return False
    return r.returncode == 0 and r.stdout.strip().endswith("ok")


def choose() -> str:
    """The variant to use in this process (probing at most once)."""
    global _chosen
    if _chosen is not None:
        return _chosen
    forced = os.environ.get(ENV_VARIANT, "").strip()
    if forced:
        _chosen = forced
        how = f"from ${ENV_VARIANT}"
    else:
        _chosen = next((v for v in CANDIDATES[:-1] if probe(v)), CANDIDATES[-1])
        how = "probed"
    print(f"stripebench.scenes: Mitsuba variant {_chosen} ({how})", file=sys.stderr)
    return _chosen


def check_forced() -> Optional[str]:
    """Check ``$STRIPEBENCH_VARIANT`` before any work: None when it is unset, else the variant.

    The name must be a ``*_mono`` or ``*_rgb`` variant of the installed Mitsuba, and a
    ``cuda_*`` (``llvm_*``) one needs Dr.Jit's CUDA (LLVM) backend on this machine (a GPU
    and its driver; a loadable libLLVM). Cheap: Mitsuba and Dr.Jit are imported, nothing
    is compiled or rendered.

    Raises
    ------
    VariantError
        One line naming the value and the variants that can work here.
    """
    forced = os.environ.get(ENV_VARIANT, "").strip()
    if not forced:
        return None
    if "drjit" not in sys.modules and "DRJIT_LIBLLVM_PATH" not in os.environ:
        lib = find_libllvm()
        if lib:
            os.environ["DRJIT_LIBLLVM_PATH"] = lib
    import drjit as dr
    import mitsuba as mi

    backends = {"cuda": dr.has_backend(dr.JitBackend.CUDA), "llvm": dr.has_backend(dr.JitBackend.LLVM),
                "scalar": True}
    usable = [v for v in mi.variants() if v.endswith(("_mono", "_rgb")) and backends.get(v.split("_")[0], False)]
    if forced not in mi.variants() or not forced.endswith(("_mono", "_rgb")):
        raise VariantError(f"${ENV_VARIANT} must name a mono or RGB Mitsuba variant, got {forced!r}; "
                           f"usable here: {', '.join(usable)}")
    if forced not in usable:
        need = {"cuda": "a CUDA GPU and driver", "llvm": "a loadable libLLVM"}[forced.split("_")[0]]
        raise VariantError(f"${ENV_VARIANT} = {forced!r} needs {need}, which this machine lacks; "
                           f"usable here: {', '.join(usable)}")
    return forced


def mitsuba():
    """Import Mitsuba with the chosen variant set and return the module."""
    if "drjit" not in sys.modules and "DRJIT_LIBLLVM_PATH" not in os.environ:
        lib = find_libllvm()
        if lib:
            os.environ["DRJIT_LIBLLVM_PATH"] = lib
    variant = choose()
    import mitsuba as mi

    if mi.variant() != variant:
        if variant not in mi.variants():
            raise ValueError(f"`{ENV_VARIANT}` names a variant this Mitsuba lacks: {variant!r}; "
                             f"valid: {', '.join(mi.variants())}")
        mi.set_variant(variant)
    return mi


def active_variant() -> str:
    """Name of the variant :func:`mitsuba` sets (probing if needed)."""
    return choose()


def is_mono(variant: str) -> bool:
    """True for ``*_mono`` variants (one channel); otherwise RGB with equal channels."""
    return variant.endswith("_mono")
