"""Check that the DP kernels of this checkout compute what those of an earlier revision did, bit for bit.

The speed work on the exact solver (``trackers._dp_kernels``) and on ``dp_gap``'s sweep
(``trackers._dp_gap``) changed how the loops run, not what they compute. This script loads both
kernel modules as they were at ``REV`` (``git show REV:trackers/...``, into a temporary folder) and
compares, on every frame of ``bench.studies.perf.frames.varied_frames(2, seed=0)`` (72 8-bit frames)
and on a float64 signed difference of every third of them (24 frames, as a laser-off frame gives):

* the half costs and each row's least one and its leftmost column (``half_cost_u8`` / ``half_cost_float``);
* the bounded distance field ``D`` of ``accumulate``, its sweep count, the labelled optimal nodes
  (``optimal_nodes``) and the backtracked path, for 4- and 8-connectivity at ``h_weight`` 1 and 0.25
  (the new kernels with and without the rightmost minima given);
* the exact field (``bound=False``, 8-connectivity, ``h_weight`` 0.5) on the frames below 960 wide;
* ``dp_gap``'s fields ``F`` and ``Foff`` (``sweep``) with the tracker's own off and switch costs,
  8-connectivity at 0.25 and 4-connectivity at 1.

Prints the number of comparisons and of differences (each difference named); exit status 1 if any.
Run with the project's Python from a git checkout: ``python scripts/dp_kernel_identity.py [REV]``
(default ``79eba0f``, the last revision with the scalar loops).
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the repository root

import trackers  # noqa: E402
from bench.studies.perf.frames import varied_frames  # noqa: E402
from trackers import _dp_gap as G  # noqa: E402
from trackers import _dp_kernels as K  # noqa: E402
from trackers.dp import _half_cost  # noqa: E402

DEFAULT_REV = "79eba0f"
CONFIGS = ((False, 1.0), (False, 0.25), (True, 1.0), (True, 0.25))


def load_old(rev: str, path: str, folder: Path, name: str):
    """The module ``path`` as it was at ``rev``, imported from ``folder`` under ``name``."""
    text = subprocess.run(["git", "show", f"{rev}:{path}"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    file = folder / f"{name}.py"
    file.write_text(text)
    spec = importlib.util.spec_from_file_location(name, file)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def frames():
    out = list(varied_frames(2, seed=0))
    rng = np.random.default_rng(5)
    for label, img in out[::3]:
        out.append((f"{label} float", img.astype(np.float64) - rng.integers(0, 30, img.shape)))
    return out


def compare(OK, OG) -> tuple[int, list[str]]:
    count = 0
    diffs = []
    gap = trackers.make("dp_gap")
    for label, img in frames():
        H, W = img.shape
        hc0 = np.empty((H, W))
        rm0 = np.empty(H)
        ce0 = np.empty(H, np.int64)
        (OK.half_cost_u8 if img.dtype == np.uint8 else OK.half_cost_float)(img, 1.0, hc0, rm0, ce0)
        hc, rm, ce, rc = _half_cost(img, 1.0)
        count += 1
        if not (hc0.tobytes() == hc.tobytes() and rm0.tobytes() == rm.tobytes() and np.array_equal(ce0, ce)):
            diffs.append(f"{label}: half costs")
        for conn8, hw in CONFIGS:
            D0, D1, D2 = (np.empty_like(hc) for _ in range(3))
            s0 = OK.accumulate(hc, conn8, True, D0, rm, ce, hw)
            s1 = K.accumulate(hc, conn8, True, D1, rm, ce, hw, rc)
            s2 = K.accumulate(hc, conn8, True, D2, rm, ce, hw)
            marks = [np.zeros((H, W), np.uint8) for _ in range(2)]
            rows = [np.empty(H * W, np.int64) for _ in range(4)]
            cols = [np.empty(H * W, np.int64) for _ in range(4)]
            n0 = OK.optimal_nodes(D0, hc, conn8, 1e-11, marks[0], rows[0], cols[0], hw)
            n1 = K.optimal_nodes(D1, hc, conn8, 1e-11, marks[1], rows[1], cols[1], hw)
            p0 = OK.backtrack(D0, hc, conn8, rows[2], cols[2], hw)
            p1 = K.backtrack(D1, hc, conn8, rows[3], cols[3], hw)
            count += 1
            same = (D0.tobytes() == D1.tobytes() == D2.tobytes() and s0 == s1 == s2 and np.array_equal(*marks)
                    and n0 == n1 and p0 == p1 and np.array_equal(rows[2][:p0], rows[3][:p1])
                    and np.array_equal(cols[2][:p0], cols[3][:p1]))
            if not same:
                diffs.append(f"{label}: {8 if conn8 else 4}-conn h_weight={hw:g} (sweeps {s0} / {s1})")
        if W < 960:
            D0, D1 = np.empty_like(hc), np.empty_like(hc)
            OK.accumulate(hc, True, False, D0, rm, ce, 0.5)
            K.accumulate(hc, True, False, D1, rm, ce, 0.5, rc)
            count += 1
            if D0.tobytes() != D1.tobytes():
                diffs.append(f"{label}: the exact field")
        off, s = gap.off_costs(img, rm)
        ho = np.full(H, 0.5 * off)
        for conn8, hw in ((True, 0.25), (False, 1.0)):
            F0, F1 = np.empty((H, W)), np.empty((H, W))
            f0, f1 = np.empty(H), np.empty(H)
            OG.sweep(hc, ho, s, conn8, hw, F0, f0)
            G.sweep(hc, ho, s, conn8, hw, F1, f1)
            count += 1
            if F0.tobytes() != F1.tobytes() or f0.tobytes() != f1.tobytes():
                diffs.append(f"{label}: dp_gap {8 if conn8 else 4}-conn h_weight={hw:g}")
    return count, diffs


def main() -> int:
    rev = sys.argv[1] if len(sys.argv) > 1 else DEFAULT_REV
    with tempfile.TemporaryDirectory() as tmp:
        OK = load_old(rev, "trackers/_dp_kernels.py", Path(tmp), "old_dp_kernels")
        OG = load_old(rev, "trackers/_dp_gap.py", Path(tmp), "old_dp_gap")
        count, diffs = compare(OK, OG)
    for d in diffs:
        print("differs:", d)
    print(f"{count} comparisons against {rev}, {len(diffs)} differences")
    return 1 if diffs else 0


if __name__ == "__main__":
    raise SystemExit(main())
