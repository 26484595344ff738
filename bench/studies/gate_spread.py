"""The gated metrics' spread across machine configurations, and the gate's tolerances from it.

The regression gate (:mod:`bench.run.gate`) must pass on whatever CI machine a
submission lands on, so its tolerances must cover what changes between
machines. This module measures that: it runs a gate's command (the ``ci``
profile, or the real-photograph set) once per :class:`Machine`, each in a
child process with its own empty render cache, and compares every gated
metric of every (experiment, tracker, region) across them.

Usage (``stripebench spread``, :func:`study`; ``python -m bench.cli.gate_spread`` is the same)::

    stripebench spread --out /tmp/spread                   # measure, print the table
    stripebench spread --out /tmp/spread --write results/baselines
    stripebench spread --out /tmp/spread --gates real --machines here,avx2

``--write DIR`` writes ``DIR/ci.json`` and ``DIR/real.json`` from the
reference machine's runs (:data:`REFERENCE`) with the derived tolerances
(:func:`derive_tolerances`) and their provenance in ``tolerance_source``;
the detail (per-metric spreads, the tolerances the ungated machines would
need, wall times) goes to ``OUT/spread.json``. ``--reuse`` reads runs already
finished in ``--out`` instead of running them again.

A machine's *spread* for one entry and metric is the range (max - min) of its
values over the gated machines; a metric's tolerance is the spread times
:data:`SAFETY`, floored at the default tolerance (:data:`bench.run.gate.TOLERANCES`):
``abs = max(abs_default, max over entries (SAFETY * range - rel_default * min|value|))``,
``rel = rel_default``, so every measured difference (times the factor) passes
and no tolerance is tighter than today's. An entry whose value is NaN on some
machines only cannot be covered by any tolerance (the gate fails a NaN flip):
it is counted and makes the procedure exit 1.

Another real machine cannot be emulated here (its CPU's own kernels, e.g. Embree's). ``--against FILE``
brings one in: a committed baseline that machine wrote (same gate, same renderer string) is compared with
this machine's reference run, entry by entry, and an entry whose difference times :data:`SAFETY` its
metric's tolerance does not cover gets a tolerance of its own (:func:`derive_entry_tolerances`, the
baseline's ``entry_tolerances``): the entries that a CPU moves are widened, every other entry keeps the
metric's tolerance.

Machines marked ``gated = False`` (Dr.Jit's native 16-wide code, the scalar
variant) render differently by construction: ``stripebench check`` refuses to
compare across renderers (:func:`bench.run.gate.renderer_difference`), so their
spread is measured and printed but not used for tolerances.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

from bench.run import gate

__all__ = ["Machine", "MACHINES", "REFERENCE", "SAFETY", "GATES", "entry_ranges", "metric_spread",
           "derive_tolerances", "derive_entry_tolerances", "measure", "study"]

#: The factor between the measured spread and the tolerance.
SAFETY = 2.0

# numpy's and numba's kernels for an AVX2 CPU without AVX-512 (numpy's dispatch names, numba's and
# OpenBLAS's CPU names); Dr.Jit's kernels are the portable ones on every such CPU anyway
_AVX2_ENV = {"NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR", "NUMBA_CPU_NAME": "haswell",
             "OPENBLAS_CORETYPE": "Haswell"}


@dataclass(frozen=True)
class Machine:
    """A configuration of this machine that stands in for another CI machine.

    Attributes
    ----------
    name : str
        Short name (the run folders are ``<gate>-<name>``).
    stands_for : str
        The machine it emulates, in words.
    env : mapping
        Environment variables of the child process (on top of this process's).
    threads : int or None
        Dr.Jit's thread count in the run process (None: Dr.Jit's default, one per core).
    render_ahead : bool
        Whether the run may start its render-ahead helper (``--no-render-ahead`` otherwise).
    gated : bool
        Whether the gate must pass on it (its spread sets tolerances).
    """

    name: str
    stands_for: str
    env: Mapping[str, str] = field(default_factory=dict)
    threads: int | None = None
    render_ahead: bool = True
    gated: bool = True


MACHINES: tuple[Machine, ...] = (
    Machine("here", "this machine as CI runs it (its cores, default settings)"),
    Machine("one-core", "a 1-core machine: one Dr.Jit thread, no render-ahead helper", threads=1,
            render_ahead=False),
    Machine("four-cores", "a 4-core machine: four Dr.Jit threads (oversubscribed here)", threads=4),
    Machine("avx2", "an x86-64 CPU with AVX2 but no AVX-512: numpy, numba and OpenBLAS kernels for it",
            env=_AVX2_ENV),
    Machine("native-avx512", "this CPU with Dr.Jit's own 16-wide AVX-512 code (the renders before the fix)",
            env={"STRIPEBENCH_LLVM_TARGET": "native"}, gated=False),
    Machine("native-avx2", "an AVX2 CPU with Dr.Jit's own 8-wide code and AVX intrinsics (before the fix)",
            env={"STRIPEBENCH_LLVM_TARGET": "haswell/8/+avx,+avx2,+fma,+f16c,+bmi,+bmi2,+lzcnt,+movbe,+popcnt",
                 **_AVX2_ENV}, gated=False),
    Machine("scalar", "a machine without a usable LLVM: Mitsuba's scalar_rgb variant",
            env={"STRIPEBENCH_VARIANT": "scalar_rgb"}, gated=False),
)
#: The machine whose runs become the baselines.
REFERENCE = "here"
#: What every gate run is rendered with (``.ci/run`` sets the same): the portable LLVM target, whose
#: frames are the same on every x86-64-v3 CPU (a machine's own ``env`` overrides it)
GATE_ENV = {"STRIPEBENCH_LLVM_TARGET": "portable"}

#: The trackers of the real-photograph gate (``.ci/run`` passes the same list; a test checks it).
REAL_TRACKERS = "blais_rioux,centroid,com_bg,dp4,dp8,dp8_subpixel,dp_gap,gauss3,learned,parabolic,steger,threshold"
#: gate -> (CLI arguments of its run before ``--out``, baseline file name)
GATES: dict[str, tuple[tuple[str, ...], str]] = {
    "ci": (("run", "--profile", "ci", "--force", "--quiet"), "ci.json"),
    "real": (("real", "bench/data/real", "--quiet"), "real.json"),
}


def _nan(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def entry_ranges(docs: Mapping[str, dict]) -> dict[tuple[str, str], dict]:
    """Per (entry, metric) of baseline-like documents (``{"metrics": {entry: {metric: value}}}``),
    the spread over the documents.

    Returns
    -------
    dict
        ``(entry, metric) -> {"range": max - min (0 with fewer than two numbers), "min_abs": the
        smallest |value|, "nan_flip": some values are NaN/None and others not, "missing": names of
        the documents without it}``.

    Examples
    --------
    >>> r = entry_ranges({"a": {"metrics": {"e/t/all": {"px_mae": 1.0}}},
    ...                   "b": {"metrics": {"e/t/all": {"px_mae": 1.25}}}})
    >>> r[("e/t/all", "px_mae")]["range"], r[("e/t/all", "px_mae")]["nan_flip"]
    (0.25, False)
    """
    if not docs:
        raise ValueError("`docs` must hold at least one document, got none")
    keys = sorted({(e, m) for d in docs.values() for e, ms in d["metrics"].items() for m in ms})
    out = {}
    for e, m in keys:
        vals, missing = [], []
        for name, d in docs.items():
            entry = d["metrics"].get(e)
            if entry is None or m not in entry:
                missing.append(name)
            else:
                vals.append(entry[m])
        nums = [float(v) for v in vals if not _nan(v)]
        out[(e, m)] = {"range": (max(nums) - min(nums)) if len(nums) > 1 else 0.0,
                       "min_abs": min((abs(v) for v in nums), default=0.0),
                       "nan_flip": 0 < len(nums) < len(vals), "missing": missing}
    return out


def metric_spread(ranges: Mapping[tuple[str, str], dict]) -> dict[str, dict]:
    """Per metric: the largest range of :func:`entry_ranges` and its entry, how many entries
    differ at all, the NaN flips and the entries missing somewhere.

    Examples
    --------
    >>> metric_spread({("e/t/all", "px_mae"): {"range": 0.25, "min_abs": 1.0, "nan_flip": False,
    ...                                       "missing": []}})["px_mae"]["max_range"]
    0.25
    """
    out: dict[str, dict] = {}
    for (e, m), r in sorted(ranges.items()):
        s = out.setdefault(m, {"max_range": 0.0, "entry": "", "entries": 0, "differing": 0, "nan_flips": [],
                               "missing": []})
        s["entries"] += 1
        if r["range"] > 0:
            s["differing"] += 1
        if r["range"] > s["max_range"]:
            s["max_range"], s["entry"] = r["range"], e
        if r["nan_flip"]:
            s["nan_flips"].append(e)
        if r["missing"]:
            s["missing"].append(e)
    return out


def _ceil_sig(x: float, digits: int = 2) -> float:
    """``x`` rounded up to ``digits`` significant digits (0 stays 0)."""
    if x <= 0:
        return 0.0
    scale = 10 ** (math.floor(math.log10(x)) - digits + 1)
    return float(round(math.ceil(x / scale - 1e-9) * scale, 12))


def _abs_needed(r: dict, rel: float, safety: float) -> float:
    """The least ``abs`` with ``abs + rel * |value| >= safety * range`` at an entry's smallest |value|
    (:func:`entry_ranges`' ``r``)."""
    return safety * r["range"] - rel * r["min_abs"]


def derive_tolerances(ranges: Mapping[tuple[str, str], dict], floors: Mapping[str, tuple[str, float, float]],
                      safety: float = SAFETY) -> dict[str, dict]:
    """The gate's tolerances from the measured spread, floored at ``floors``.

    Parameters
    ----------
    ranges : mapping
        :func:`entry_ranges` over the gated machines' documents.
    floors : mapping
        ``metric -> (direction, abs, rel)``, the default tolerances (:data:`bench.run.gate.TOLERANCES`).
    safety : float
        The factor on the measured spread, >= 1.

    Returns
    -------
    dict
        ``metric -> {"direction", "abs", "rel"}`` (the baseline's ``tolerances`` block): ``rel`` is the
        floor's; ``abs = max(abs floor, max over entries (safety * range - rel * min|value|))`` rounded up
        to two significant digits, so ``abs + rel * |value| >= safety * range`` for every entry.

    Raises
    ------
    ValueError
        ``safety`` below 1 or not finite (echoed).

    Examples
    --------
    >>> r = {("e/t/all", "coverage"): {"range": 0.02, "min_abs": 0.9, "nan_flip": False, "missing": []}}
    >>> derive_tolerances(r, {"coverage": ("higher", 0.01, 0.0)}, safety=2.0)
    {'coverage': {'direction': 'higher', 'abs': 0.04, 'rel': 0.0}}
    >>> derive_tolerances({}, {"coverage": ("higher", 0.01, 0.0)})
    {'coverage': {'direction': 'higher', 'abs': 0.01, 'rel': 0.0}}
    """
    if not (isinstance(safety, (int, float)) and math.isfinite(safety) and safety >= 1):
        raise ValueError(f"`safety` must be a number >= 1, got {safety!r}")
    out = {}
    for m, (direction, a, rel) in floors.items():
        need = max((_abs_needed(r, rel, safety) for (_, mm), r in ranges.items() if mm == m), default=0.0)
        out[m] = {"direction": direction, "abs": max(a, _ceil_sig(need)), "rel": rel}
    return out


def derive_entry_tolerances(ranges: Mapping[tuple[str, str], dict], tolerances: Mapping[str, dict],
                            safety: float = SAFETY) -> dict[str, dict]:
    """The tolerances of single entries whose measured spread, times ``safety``, their metric's tolerance does
    not cover.

    Parameters
    ----------
    ranges : mapping
        :func:`entry_ranges` over documents of the same gate (this machine's reference run and another machine's
        baseline).
    tolerances : mapping
        ``metric -> {"direction", "abs", "rel"}`` (:func:`derive_tolerances`).
    safety : float
        The factor on the measured spread, >= 1.

    Returns
    -------
    dict
        ``entry -> metric -> {"abs", "rel"}`` (the baseline's ``entry_tolerances``; empty when every entry is
        covered): ``rel`` is the metric's, ``abs`` the least that covers ``safety * range`` at the entry's
        smallest |value|, rounded up to two significant digits. NaN flips are left out (no tolerance covers them).

    Examples
    --------
    >>> t = {"px_mae": {"direction": "lower", "abs": 0.05, "rel": 0.05}}
    >>> r = {("a/t/all", "px_mae"): {"range": 0.01, "min_abs": 1.0, "nan_flip": False, "missing": []},
    ...      ("b/t/all", "px_mae"): {"range": 0.2, "min_abs": 1.0, "nan_flip": False, "missing": []}}
    >>> derive_entry_tolerances(r, t)
    {'b/t/all': {'px_mae': {'abs': 0.35, 'rel': 0.05}}}
    """
    derive_tolerances({}, {}, safety)  # checks `safety`
    out: dict[str, dict] = {}
    for (e, m), r in sorted(ranges.items()):
        t = tolerances.get(m)
        if t is None or r["nan_flip"]:
            continue
        need = _abs_needed(r, t["rel"], safety)
        if need > t["abs"]:
            out.setdefault(e, {})[m] = {"abs": _ceil_sig(need), "rel": t["rel"]}
    return out


def _run_one(gate_name: str, machine: Machine, out: Path, argv_extra: Sequence[str], repo: Path) -> tuple[Path, float]:
    args, _ = GATES[gate_name]
    run_dir = out / f"{gate_name}-{machine.name}"
    cmd = [sys.executable, "-m", "bench.studies.gate_spread", "_child", str(machine.threads or 0), "--", *args,
           "--out", str(run_dir), *argv_extra]
    if gate_name == "ci" and not machine.render_ahead:
        cmd.append("--no-render-ahead")
    env = {**os.environ, **GATE_ENV, **machine.env, "STRIPEBENCH_CACHE_DIR": str(out / f"cache-{machine.name}"),
           "PYTHONPATH": os.pathsep.join([str(repo), *filter(None, [os.environ.get("PYTHONPATH")])])}
    t0 = time.perf_counter()
    r = subprocess.run(cmd, cwd=repo, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if r.returncode != 0:
        tail = (r.stderr.strip().splitlines() or ["(no output)"])[-1]
        raise RuntimeError(f"the {gate_name} run on machine {machine.name!r} failed (exit {r.returncode}): {tail}")
    return run_dir, wall


def measure(out, *, gates: Sequence[str] = ("ci", "real"), machines: Sequence[Machine] = MACHINES,
            real_trackers: str = "", repo=None, reuse: bool = False, log=print) -> dict:
    """Run every gate on every machine (child processes, own render caches under ``out``) and
    return ``{gate: {machine name: baseline-like document}}`` with each run's wall time (``wall_s``,
    None for a run that ``reuse`` found finished in ``out`` and read instead of running again)."""
    repo = Path(repo) if repo is not None else Path(__file__).resolve().parents[2]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    docs: dict[str, dict] = {}
    for g in gates:
        extra = ("--trackers", real_trackers) if g == "real" and real_trackers else ()
        docs[g] = {}
        for mach in machines:
            run_dir, wall = out / f"{g}-{mach.name}", None
            if not (reuse and (run_dir / "summary.json").is_file()):
                run_dir, wall = _run_one(g, mach, out, extra, repo)
            doc = gate.baseline_from_run(run_dir)
            doc["wall_s"] = wall
            docs[g][mach.name] = doc
            took = "reused" if wall is None else f"{wall:.0f} s"
            log(f"gate_spread: {g} on {mach.name}: {took}, renderer {doc.get('renderer') or '-'}")
    return docs


def _table(g: str, docs: Mapping[str, dict], machines: Sequence[Machine], tols: Mapping[str, dict]) -> str:
    """The markdown table of a gate: per metric the gated machines' spread, each other machine's
    against the reference, and the tolerance."""
    gated = {m.name: docs[m.name] for m in machines if m.gated and m.name in docs}
    others = {m.name: metric_spread(entry_ranges({REFERENCE: docs[REFERENCE], m.name: docs[m.name]}))
              for m in machines if not m.gated and m.name in docs}
    head = ["metric", "entries", f"gated ({', '.join(gated)})", *(f"{n} vs {REFERENCE}" for n in others),
            "tolerance: abs + rel × baseline"]
    lines = [f"{g}: the largest range of each gated metric over its entries (entries that differ at all)", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]

    def cell(s):
        flips = f", {len(s['nan_flips'])} NaN flips" if s["nan_flips"] else ""
        return f"{s['max_range']:.4g} ({s['differing']}{flips})"

    for metric, s in metric_spread(entry_ranges(gated)).items():
        t = tols.get(metric, {})
        row = [metric, str(s["entries"]), cell(s), *(cell(o[metric]) if metric in o else "-" for o in others.values()),
               f"{t['abs']:g} + {t['rel']:g}" if t else "-"]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def _child(argv: Sequence[str]) -> int:
    """``python -m bench.studies.gate_spread _child THREADS -- CLI ARGS``: the CLI with Dr.Jit's thread count set."""
    threads = int(argv[0])
    if threads > 0:
        from scenes import variant

        if not variant.choose().startswith("scalar"):
            variant.mitsuba()
            import drjit

            drjit.set_thread_count(threads)
    import runpy

    # the command line as a shell would run it (a study does not import the command layer)
    rest = list(argv[2:]) if len(argv) > 1 and argv[1] == "--" else list(argv[1:])
    sys.argv = ["stripebench", *rest]
    try:
        runpy.run_module("bench.cli", run_name="__main__", alter_sys=True)
    except SystemExit as exc:
        return int(exc.code or 0) if not isinstance(exc.code, str) else 2
    return 0


def study(*, out, gates: str = "ci,real", machines: str = ",".join(m.name for m in MACHINES), safety: float = SAFETY,
          reuse: bool = False, write=None, against=()) -> int:
    """Run the procedure (``stripebench spread``): measure every gate on every machine, print the table,
    write ``OUT/spread.json`` and, with ``write``, the baselines.

    Parameters
    ----------
    out : path
        Folder for the runs, their caches and ``spread.json``.
    gates : str
        Comma-separated gates (some of :data:`GATES`).
    machines : str
        Comma-separated machines (some of :data:`MACHINES`, including :data:`REFERENCE`).
    safety : float
        The factor on the spread.
    reuse : bool
        Read the runs already finished in ``out`` (same machines) instead of running them again.
    write : path, optional
        Write ``WRITE/ci.json`` and ``WRITE/real.json`` from the reference runs with the derived tolerances.
    against : sequence of path
        Baselines other machines wrote for the one gate measured (same renderer): their entries beyond the
        tolerances get their own (:func:`derive_entry_tolerances`).

    Returns
    -------
    int
        0, 1 (NaN flips: no tolerance covers them) or 2 (a bad option, a failed run: one line on stderr,
        ``gate_spread: ...``).
    """
    out = Path(out)
    write = None if write is None else Path(write)
    try:
        gates_text, gates = gates, [g.strip() for g in gates.split(",") if g.strip()]
        bad = [g for g in gates if g not in GATES]
        if bad or not gates:
            raise ValueError(f"`--gates` must name some of {', '.join(GATES)}, got {gates_text!r}")
        by_name = {m.name: m for m in MACHINES}
        machines_text = machines
        names = [n.strip() for n in machines_text.split(",") if n.strip()]
        bad = [n for n in names if n not in by_name]
        if bad or REFERENCE not in names:
            raise ValueError(f"`--machines` must name some of {', '.join(by_name)} including {REFERENCE!r}, "
                             f"got {machines_text!r}")
        machines = [by_name[n] for n in names]
        derive_tolerances({}, {}, safety)  # validates --safety before minutes of runs
        if write is not None and write.exists() and not write.is_dir():
            raise ValueError(f"`--write` must be a folder, got {str(write)!r} (not a folder)")
        against = [Path(a) for a in against]
        if against and len(gates) != 1:
            raise ValueError(f"`--against` compares baselines of one gate: name it with `--gates`, got {gates_text!r}")
        others = {}
        for a in against:
            try:
                others[str(a)] = gate.load_baseline(a)
            except (OSError, ValueError) as exc:
                raise ValueError(f"`--against` {str(a)!r}: {exc}") from None
        real_trackers = REAL_TRACKERS if "real" in gates else ""
        docs = measure(out, gates=gates, machines=machines, real_trackers=real_trackers, reuse=reuse,
                       log=lambda s: print(s, file=sys.stderr))
    except (ValueError, RuntimeError, FileNotFoundError) as exc:
        print(f"gate_spread: {exc}", file=sys.stderr)
        return 2
    report, status = {"safety": safety, "machines": [vars(m) | {"env": dict(m.env)} for m in machines]}, 0
    for g in gates:
        gated = {m.name: docs[g][m.name] for m in machines if m.gated}
        ranges = entry_ranges(gated)
        floors = gate.REAL_TOLERANCES if g == "real" else gate.TOLERANCES
        tols = derive_tolerances(ranges, floors, safety)
        ref = docs[g][REFERENCE]
        for name, doc in others.items():
            why = gate.renderer_difference(doc, ref)
            if why:
                print(f"gate_spread: against {name} cannot widen the {g} gate: {why}", file=sys.stderr)
                return 2
        named = {REFERENCE: ref, **{f"against {n}": d for n, d in others.items()}}  # apart from the machines' names
        against_ranges = entry_ranges(named) if others else {}
        entry_tols = derive_entry_tolerances(against_ranges, tols, safety) if others else {}
        if others:
            pairs = sum(len(v) for v in entry_tols.values())
            print(f"gate_spread: {g}: against {', '.join(others)}: {pairs} (entry, metric) "
                  f"pairs in {len(entry_tols)} entries move more than their metric's tolerance allows and get "
                  "their own", file=sys.stderr)
        spread = metric_spread(ranges)
        flips = sorted({e for s in spread.values() for e in s["nan_flips"]})
        if flips:
            print(f"gate_spread: {g}: {len(flips)} entries are NaN on some gated machines only (no tolerance "
                  f"covers that), e.g. {flips[0]}", file=sys.stderr)
            status = 1
        print(_table(g, docs[g], machines, tols) + "\n")
        informational = [(m, {REFERENCE: docs[g][REFERENCE], m.name: docs[g][m.name]}) for m in machines
                         if not m.gated]
        source = {"procedure": "stripebench spread", "safety": safety,
                  "machines": [m.name for m in machines if m.gated],
                  "spread": {m: {"max_range": s["max_range"], "entry": s["entry"], "differing": s["differing"]}
                             for m, s in spread.items()}}
        if others:
            source["against"] = [{"baseline": n, "git_revision": d.get("git_revision", ""),
                                  "renderer": d.get("renderer", ""),
                                  "spread": {m: {"max_range": s["max_range"], "entry": s["entry"],
                                                 "differing": s["differing"]}
                                             for m, s in metric_spread(against_ranges).items()}}
                                 for n, d in others.items()]
        report[g] = {"tolerances": tols, "source": source,
                     "wall_s": {n: d["wall_s"] and round(d["wall_s"], 1) for n, d in docs[g].items()},
                     "informational": {m.name: metric_spread(entry_ranges(pair)) for m, pair in informational},
                     # the tolerances each ungated machine would need against the reference (not used)
                     "tolerances_if_gated": {m.name: derive_tolerances(entry_ranges(pair), floors, safety)
                                             for m, pair in informational},
                     "renderers": {n: d.get("renderer", "") for n, d in docs[g].items()},
                     "entry_tolerances": entry_tols}
        if write is not None and not flips:
            path = write / GATES[g][1]
            doc = gate.write_baseline(out / f"{g}-{REFERENCE}", path, tolerances=tols, tolerance_source=source,
                                      entry_tolerances=entry_tols)
            print(f"gate_spread: wrote {path} ({len(doc['metrics'])} entries)", file=sys.stderr)
    (out / "spread.json").write_text(json.dumps(report, indent=1, sort_keys=True, default=str) + "\n")
    return status


if __name__ == "__main__":
    # the child runs of :func:`measure` (the procedure itself is ``stripebench spread``)
    if sys.argv[1:2] != ["_child"]:
        sys.exit("usage: python -m bench.studies.gate_spread _child THREADS -- CLI ARGS "
                 "(the procedure is `stripebench spread`)")
    sys.exit(_child(sys.argv[2:]))
