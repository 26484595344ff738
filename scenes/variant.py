"""Choosing and loading the Mitsuba variant safely.

Order of preference: ``cuda_ad_mono`` (a working GPU), ``llvm_ad_mono`` (a working
LLVM), ``scalar_rgb`` (always works; no ``scalar_mono`` exists, so scenes use
equal RGB values and one channel is read back).  ``STRIPEBENCH_VARIANT``
overrides the choice.

A broken LLVM (Debian's 14/15/16 with drjit 1.5) *aborts the whole process*
inside the JIT, so each candidate is first tried in a child process that
renders a tiny scene; only a variant that survived there is set in this process.

The LLVM variant's code is generated for a target: Dr.Jit by default compiles for the
host (``-march=native``) with the host's vector width (16 lanes with AVX-512, 8 with
AVX2), and the width changes the order of the sums inside a render (per-pixel sample
accumulation, the light tracer's splats), hence the last float bits of every pass and,
through the 8-bit sensor, some metrics. :data:`PORTABLE_TARGET` (``x86-64-v3``: AVX2 +
FMA, 8 lanes, no CPU-specific intrinsics), asked for by ``portable``, renders
bit-identical passes on every x86-64 CPU that has those instructions (measured:
docs/gate.md). A configuration asks for a target with its ``llvm_target``
(:func:`request_llvm_target`; the ``ci`` profile asks for ``portable``);
``STRIPEBENCH_LLVM_TARGET`` overrides it: ``""``/``native`` (Dr.Jit's own choice, the
default), ``portable`` or ``CPU/WIDTH[/FEATURES]`` (e.g. ``haswell/8/+avx2,+fma``, used to
emulate other CPUs); :func:`llvm_target` names the one in use (it is part of the render
cache key).
Before drjit is imported, ``DRJIT_LIBLLVM_PATH`` is pointed at a
``libLLVM.so.19*``/``libLLVM-19.so`` (or newer) found in the usual library
folders, unless the variable is already set.  The choice is printed to stderr
once per process and cached for the process's lifetime (it is a property of the
machine, not of any frame).
"""

from __future__ import annotations

import functools
import glob
import os
import re
import subprocess
import sys
from typing import Optional

__all__ = ["CANDIDATES", "PORTABLE_TARGET", "ENV_LLVM_TARGET", "VariantError", "find_libllvm", "probe", "choose",
           "check_forced", "mitsuba", "active_variant", "is_mono", "parse_llvm_target", "llvm_target",
           "host_supports_portable", "renderer", "request_llvm_target"]

CANDIDATES = ("cuda_ad_mono", "llvm_ad_mono", "scalar_rgb")
ENV_VARIANT = "STRIPEBENCH_VARIANT"
_LLVM_DIRS = ("/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib",
              "/usr/local/lib", "/opt/homebrew/opt/llvm/lib", "/usr/local/opt/llvm/lib")
_MIN_LLVM = 17
_chosen: Optional[str] = None

ENV_LLVM_TARGET = "STRIPEBENCH_LLVM_TARGET"
#: (target CPU, LLVM feature string or None, vector width) of the LLVM variant's kernels on an
#: x86-64 CPU with AVX2 and FMA. No feature string: Dr.Jit then picks no x86-specific intrinsic
#: (its choice of those tests the feature string), only portable LLVM operations.
PORTABLE_TARGET = ("x86-64-v3", None, 8)
# /proc/cpuinfo flags of x86-64-v3 (abm: lzcnt); sse4.2 etc. are implied by these
_V3_FLAGS = ("avx", "avx2", "fma", "bmi1", "bmi2", "f16c", "movbe", "abm", "xsave")
_target: Optional[str] = None  # the descriptor of the target applied in this process
_asked: Optional[str] = None  # the value request_llvm_target put in the environment (not the user's override)
_DRJIT_SYMBOLS = {"set": "_Z19jit_llvm_set_targetPKcS0_j", "width": "_Z21jit_llvm_vector_widthv",
                  "cpu": "_Z19jit_llvm_target_cpuv", "features": "_Z24jit_llvm_target_featuresv"}

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
    target = ""
    if _chosen.startswith("llvm"):
        t = _requested()
        target = f", LLVM target {_describe(t) if t is not None else 'native'}"
    print(f"stripebench.scenes: Mitsuba variant {_chosen} ({how}){target}", file=sys.stderr)
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


def parse_llvm_target(value: str):
    """The LLVM target named by ``value`` (the syntax of ``$STRIPEBENCH_LLVM_TARGET``).

    Returns
    -------
    None or tuple
        ``None`` for ``""`` (unset: the default) or ``"native"`` (Dr.Jit's own choice for this CPU),
        :data:`PORTABLE_TARGET` for ``"portable"`` (the renders of every x86-64-v3 CPU, bit for bit:
        what the regression gate uses), else ``(cpu, features or None, width)`` from ``CPU/WIDTH[/FEATURES]``.

    Raises
    ------
    ValueError
        A malformed value (names the variable, echoes the value).

    Examples
    --------
    >>> parse_llvm_target("haswell/8/+avx2,+fma")
    ('haswell', '+avx2,+fma', 8)
    >>> parse_llvm_target("native") is None, parse_llvm_target("portable") == PORTABLE_TARGET
    (True, True)
    >>> parse_llvm_target("haswell/6")
    Traceback (most recent call last):
    ...
    ValueError: `STRIPEBENCH_LLVM_TARGET` must be 'portable', 'native' or CPU/WIDTH[/FEATURES] with WIDTH a power of two in 1..64, got 'haswell/6'
    """
    v = value.strip()
    if v == "portable":
        return PORTABLE_TARGET
    if v in ("", "native"):
        return None
    parts = v.split("/", 2)
    width = parts[1] if len(parts) > 1 else ""
    if len(parts) < 2 or not parts[0] or not width.isdigit() or int(width) not in (1, 2, 4, 8, 16, 32, 64):
        raise ValueError(f"`{ENV_LLVM_TARGET}` must be 'portable', 'native' or CPU/WIDTH[/FEATURES] with WIDTH "
                         f"a power of two in 1..64, got {value!r}")
    return parts[0], (parts[2] or None) if len(parts) > 2 else None, int(width)


@functools.lru_cache(maxsize=8)
def host_supports_portable(cpuinfo: str = "/proc/cpuinfo") -> bool:
    """True on an x86-64 CPU whose flags (``cpuinfo``) include every instruction set of
    :data:`PORTABLE_TARGET` (AVX2, FMA, BMI1/2, F16C, MOVBE, LZCNT); read once per path."""
    import platform

    if platform.machine().lower() not in ("x86_64", "amd64"):
        return False
    try:
        with open(cpuinfo, encoding="utf-8", errors="replace") as fh:
            text = fh.read()
    except OSError:
        return False
    m = re.search(r"^flags\s*:(.*)$", text, re.M)
    return bool(m) and set(_V3_FLAGS) <= set(m.group(1).split())


def _describe(target) -> str:
    cpu, features, width = target
    return f"{cpu}/{width}" + (f"/{features}" if features else "")


def _requested():
    """The target this process asks for: a tuple, or None for Dr.Jit's native choice (the default;
    also where ``portable`` is asked for on a CPU that cannot run it: the renderer then says so, and
    ``stripebench check`` refuses a baseline rendered with it in one line)."""
    t = parse_llvm_target(os.environ.get(ENV_LLVM_TARGET, ""))
    if t == PORTABLE_TARGET and not host_supports_portable():
        return None
    return t


def request_llvm_target(value: str) -> None:
    """Ask for the LLVM target ``value`` (a configuration's ``llvm_target``) before this
    process renders: ``""`` asks for nothing; an explicit ``$STRIPEBENCH_LLVM_TARGET`` wins
    (it is the override); otherwise the variable is set, so that helper processes started
    later (render-ahead, Dask workers) inherit it.

    Raises
    ------
    ValueError
        A malformed ``value``, or a process that already renders for another target (the
        target is fixed once drjit compiles its first kernel; run it in a fresh process).
    """
    global _asked
    wanted = parse_llvm_target(value)  # validates
    env = os.environ.get(ENV_LLVM_TARGET, "").strip()
    if not value.strip() or (env and env != _asked):  # nothing asked, or the user's own override
        return
    if _target is not None and _requested() != wanted:
        raise ValueError(f"`llvm_target` = {value!r}, but this process already renders for {_target!r}; "
                         "run it in a fresh process")
    _asked = os.environ[ENV_LLVM_TARGET] = value.strip()


def llvm_target() -> str:
    """The LLVM target of this process's renders as ``CPU/WIDTH[/FEATURES]`` (``native CPU/WIDTH``
    when Dr.Jit chose it), ``""`` for a variant that is not ``llvm_*``.

    A set target is known without loading drjit; a native one loads it (:func:`mitsuba`).
    """
    if not choose().startswith("llvm"):
        return ""
    if _target is not None:
        return _target
    t = _requested()
    if t is not None:
        return _describe(t)
    mitsuba()
    return _target


def renderer() -> str:
    """The variant and, for ``llvm_*``, the LLVM target of this process's renders, e.g.
    ``"llvm_ad_mono x86-64-v3/8"`` or ``"scalar_rgb"``: frames rendered under the same string
    are bit-identical on any machine (docs/gate.md)."""
    return f"{choose()} {llvm_target()}".strip()


def _drjit_core():
    import ctypes

    import drjit

    lib = ctypes.CDLL(os.path.join(os.path.dirname(drjit.__file__), "libdrjit-core.so"))
    try:
        fns = {k: getattr(lib, name) for k, name in _DRJIT_SYMBOLS.items()}
    except AttributeError:
        raise RuntimeError(f"drjit {drjit.__version__}'s libdrjit-core has no jit_llvm_set_target: cannot fix the "
                           f"LLVM target (set {ENV_LLVM_TARGET}=native to render for this CPU)") from None
    fns["set"].argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32]
    fns["set"].restype = None
    fns["width"].restype = ctypes.c_uint32
    fns["cpu"].restype = fns["features"].restype = ctypes.c_char_p
    return fns


def _apply_llvm_target() -> str:
    """Set the requested LLVM target in drjit (before any kernel of this process compiles);
    returns its descriptor."""
    fns = _drjit_core()
    t = _requested()
    if t is None:
        return f"native {fns['cpu']().decode()}/{fns['width']()}"
    cpu, features, width = t
    fns["set"](cpu.encode(), features.encode() if features else None, width)
    if fns["width"]() != width or fns["cpu"]().decode() != cpu:
        raise RuntimeError(f"drjit did not take the LLVM target {_describe(t)!r} (it reports "
                           f"{fns['cpu']().decode()}/{fns['width']()})")
    return _describe(t)


def mitsuba():
    """Import Mitsuba with the chosen variant set (and, for ``llvm_*``, the LLVM target of
    :func:`llvm_target` applied) and return the module."""
    global _target
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
    if _target is None and variant.startswith("llvm"):
        _target = _apply_llvm_target()
    return mi


def active_variant() -> str:
    """Name of the variant :func:`mitsuba` sets (probing if needed)."""
    return choose()


def is_mono(variant: str) -> bool:
    """True for ``*_mono`` variants (one channel); otherwise RGB with equal channels."""
    return variant.endswith("_mono")
