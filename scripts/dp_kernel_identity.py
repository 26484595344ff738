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

The kernels of this checkout are called through their public entry points (:mod:`trackers.dp_stages`,
thin calls of the kernels the trackers run); those of ``REV`` are the files as they were, loaded
from git under other names and called directly (that revision had no such entry points).

Prints the number of comparisons and of differences (each difference named); exit status 1 if any.
Run with the project's Python (installed editable from this git checkout, whose packages it
imports): ``python scripts/dp_kernel_identity.py [REV]``
(default ``79eba0f``, the last revision with the scalar loops).
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import tempfile
from pathlib import Path

import numpy as np

import trackers
from bench.studies.perf.frames import varied_frames
from trackers import dp_stages as S

ROOT = Path(__file__).resolve().parents[1]  # the git checkout the old revision is read from

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
        hc, rm, ce, rc = S.half_costs(img, 1.0)
        count += 1
        if not (hc0.tobytes() == hc.tobytes() and rm0.tobytes() == rm.tobytes() and np.array_equal(ce0, ce)):
            diffs.append(f"{label}: half costs")
        for conn8, hw in CONFIGS:
            conn = 8 if conn8 else 4
            D0 = np.empty_like(hc)
            s0 = OK.accumulate(hc, conn8, True, D0, rm, ce, hw)
            D1, s1 = S.distance_field(hc, rm, ce, conn, hw, right=rc)
            D2, s2 = S.distance_field(hc, rm, ce, conn, hw)
            mark0 = np.zeros((H, W), np.uint8)
            rows0, cols0 = np.empty(H * W, np.int64), np.empty(H * W, np.int64)
            n0 = OK.optimal_nodes(D0, hc, conn8, 1e-11, mark0, rows0, cols0, hw)
            mark1, rows1, _ = S.optimal_nodes(D1, hc, conn, hw, tol=1e-11)
            p0 = OK.backtrack(D0, hc, conn8, rows0, cols0, hw)  # bottom to top
            path_r, path_c = S.backtrack(D1, hc, conn, hw)  # top to bottom
            count += 1
            same = (D0.tobytes() == D1.tobytes() == D2.tobytes() and s0 == s1 == s2 and np.array_equal(mark0, mark1)
                    and n0 == rows1.size and p0 == path_r.size and np.array_equal(rows0[:p0][::-1], path_r)
                    and np.array_equal(cols0[:p0][::-1], path_c))
            if not same:
                diffs.append(f"{label}: {8 if conn8 else 4}-conn h_weight={hw:g} (sweeps {s0} / {s1})")
        if W < 960:
            D0 = np.empty_like(hc)
            OK.accumulate(hc, True, False, D0, rm, ce, 0.5)
            D1, _ = S.distance_field(hc, rm, ce, 8, 0.5, right=rc, exact=True)
            count += 1
            if D0.tobytes() != D1.tobytes():
                diffs.append(f"{label}: the exact field")
        off, s = gap.off_costs(img, rm)
        ho = np.full(H, 0.5 * off)
        for conn8, hw in ((True, 0.25), (False, 1.0)):
            F0, f0 = np.empty((H, W)), np.empty(H)
            OG.sweep(hc, ho, s, conn8, hw, F0, f0)
            F1, f1 = S.gap_fields(hc, ho, s, 8 if conn8 else 4, hw)
            count += 1
            if F0.tobytes() != F1.tobytes() or f0.tobytes() != f1.tobytes():
                diffs.append(f"{label}: dp_gap {8 if conn8 else 4}-conn h_weight={hw:g}")
    return count, diffs


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("rev", nargs="?", default=DEFAULT_REV, help=f"the earlier revision (default {DEFAULT_REV})")
    rev = p.parse_args(argv).rev
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
