"""The spread procedure's pure parts: ranges over machines, tolerances from them, and the
baseline format it writes (read, upgraded, refused)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from bench.studies import gate_spread as gs
from bench.run import gate
from bench.cli import main


def _doc(values):
    return {"metrics": {e: dict(ms) for e, ms in values.items()}}


def test_entry_ranges_take_max_minus_min_over_every_document():
    docs = {"a": _doc({"e/t/all": {"px_mae": 1.0, "coverage": 0.9}}),
            "b": _doc({"e/t/all": {"px_mae": 1.5, "coverage": 0.9}}),
            "c": _doc({"e/t/all": {"px_mae": 0.75, "coverage": 0.9}})}
    r = gs.entry_ranges(docs)
    assert r[("e/t/all", "px_mae")] == {"range": 0.75, "min_abs": 0.75, "nan_flip": False, "missing": []}
    assert r[("e/t/all", "coverage")]["range"] == 0.0


def test_entry_ranges_flag_nan_flips_and_missing_entries():
    docs = {"a": _doc({"e/t/all": {"px_mae": None}, "f/t/all": {"px_mae": 2.0}}),
            "b": _doc({"e/t/all": {"px_mae": 1.0}}),
            "c": _doc({"e/t/all": {"px_mae": float("nan")}})}
    r = gs.entry_ranges(docs)
    assert r[("e/t/all", "px_mae")]["nan_flip"] and r[("e/t/all", "px_mae")]["range"] == 0.0
    assert r[("f/t/all", "px_mae")]["missing"] == ["b", "c"] and not r[("f/t/all", "px_mae")]["nan_flip"]
    both_nan = gs.entry_ranges({"a": _doc({"e/t/all": {"m": None}}), "b": _doc({"e/t/all": {"m": None}})})
    assert not both_nan[("e/t/all", "m")]["nan_flip"]
    with pytest.raises(ValueError, match="at least one document"):
        gs.entry_ranges({})


def test_metric_spread_names_the_worst_entry_and_counts_the_differing_ones():
    docs = {"a": _doc({"x/t/all": {"m": 1.0}, "y/t/all": {"m": 2.0}, "z/t/all": {"m": 3.0}}),
            "b": _doc({"x/t/all": {"m": 1.1}, "y/t/all": {"m": 2.5}, "z/t/all": {"m": 3.0}})}
    s = gs.metric_spread(gs.entry_ranges(docs))["m"]
    assert s["entry"] == "y/t/all" and s["max_range"] == pytest.approx(0.5)
    assert (s["entries"], s["differing"], s["nan_flips"], s["missing"]) == (3, 2, [], [])


def test_no_spread_gives_the_floors_exactly():
    docs = {"a": _doc({"e/t/all": {m: 0.5 for m in gate.TOLERANCES}})}
    docs["b"] = json.loads(json.dumps(docs["a"]))
    tols = gs.derive_tolerances(gs.entry_ranges(docs), gate.TOLERANCES)
    assert tols == {m: {"direction": d, "abs": a, "rel": r} for m, (d, a, r) in gate.TOLERANCES.items()}


def test_derived_tolerances_cover_every_measured_difference_times_the_factor():
    rng = np.random.default_rng(3)
    floors = {"lo": ("lower", 0.01, 0.05), "hi": ("higher", 0.002, 0.0)}
    base = rng.uniform(0, 5, 30)
    docs = {f"m{k}": _doc({f"e{i}/t/all": {"lo": float(base[i] + rng.normal(0, 0.3)),
                                           "hi": float(rng.uniform(0.5, 1.0))} for i in range(30)})
            for k in range(4)}
    ranges = gs.entry_ranges(docs)
    for safety in (1.0, 2.0, 3.5):
        tols = gs.derive_tolerances(ranges, floors, safety)
        for (e, m), r in ranges.items():
            t = tols[m]
            assert t["abs"] + t["rel"] * r["min_abs"] >= safety * r["range"] - 1e-12, (e, m)
            assert t["abs"] >= floors[m][1] and t["rel"] == floors[m][2] and t["direction"] == floors[m][0]
        # and it is the smallest such two-digit value: one step less fails some entry (or is the floor)
        for m, t in tols.items():
            if t["abs"] > floors[m][1]:
                step = 10 ** (math.floor(math.log10(t["abs"])) - 1)
                worst = max(safety * r["range"] - t["rel"] * r["min_abs"] for (e, mm), r in ranges.items() if mm == m)
                assert t["abs"] - step < worst


def test_a_gated_run_passes_when_the_baseline_is_any_other_gated_machine():
    base = _doc({"e/t/all": {"px_mae": 1.0, "coverage": 0.80}})
    other = _doc({"e/t/all": {"px_mae": 1.3, "coverage": 0.74}})
    tols = gs.derive_tolerances(gs.entry_ranges({"a": base, "b": other}),
                                {"px_mae": gate.TOLERANCES["px_mae"], "coverage": gate.TOLERANCES["coverage"]})
    for b, c in ((base, other), (other, base)):
        rows = gate.compare({**b, "tolerances": tols}, c)
        assert not any(r.failed for r in rows), rows
    # with the default tolerances the same pair fails: the spread is what widened them
    assert any(r.failed for r in gate.compare(base, other))


def test_safety_below_one_is_refused_naming_the_argument():
    with pytest.raises(ValueError, match=r"`safety` must be a number >= 1, got 0\.5"):
        gs.derive_tolerances({}, gate.TOLERANCES, 0.5)
    with pytest.raises(ValueError, match="`safety`"):
        gs.derive_tolerances({}, gate.TOLERANCES, float("nan"))


def test_ceil_to_two_significant_digits_never_rounds_down():
    assert gs._ceil_sig(0.0123) == 0.013 and gs._ceil_sig(0.013) == 0.013 and gs._ceil_sig(2.01) == 2.1
    assert gs._ceil_sig(0.0) == 0.0 and gs._ceil_sig(-1.0) == 0.0
    for x in np.random.default_rng(0).uniform(1e-5, 10, 200):
        assert x <= gs._ceil_sig(float(x)) <= x * 1.1 + 1e-15


def test_the_machines_include_the_reference_and_are_named_uniquely():
    names = [m.name for m in gs.MACHINES]
    assert len(set(names)) == len(names) and gs.REFERENCE in names
    assert next(m for m in gs.MACHINES if m.name == gs.REFERENCE).gated
    assert all(not m.gated for m in gs.MACHINES if "STRIPEBENCH_VARIANT" in m.env or "STRIPEBENCH_LLVM_TARGET" in m.env)


def test_bad_arguments_are_one_line_and_exit_2(tmp_path, capsys):
    from bench.cli.gate_spread import main as old_name  # `python -m bench.cli.gate_spread`

    assert old_name(["--out", str(tmp_path), "--gates", "nope"]) == 2
    assert capsys.readouterr().err.strip() == "gate_spread: `--gates` must name some of ci, real, got 'nope'"
    assert old_name(["--out", str(tmp_path), "--machines", "one-core"]) == 2
    assert "including 'here'" in capsys.readouterr().err
    assert gs.study(out=tmp_path, safety=0.5) == 2  # the plain function: the same checks
    assert "`safety` must be a number >= 1" in capsys.readouterr().err
    from bench.cli import main  # the same procedure in the command tree: `stripebench spread`

    assert main(["spread", "--out", str(tmp_path), "--gates", "nope"]) == 2
    assert capsys.readouterr().err.strip() == "gate_spread: `--gates` must name some of ci, real, got 'nope'"


# -- the baseline format ------------------------------------------------------------------

def test_format_1_is_upgraded_on_reading(tmp_path):
    p = tmp_path / "b.json"
    cfg = {"seed": 0, "render": {}, "experiments": []}
    p.write_text(json.dumps({"format": 1, "metrics": {"e/t/all": {"px_mae": 0.1}}, "variants": ["llvm_ad_mono"],
                             "config": cfg}))
    doc = gate.load_baseline(p)
    assert (doc["format"], doc["renderer"], doc["tolerance_source"]) == (gate.FORMAT, "", "defaults")
    p.write_text(json.dumps({"format": 1, "metrics": {"e/t/all": {"px_mae": 0.1}}, "config": None}))
    with pytest.raises(ValueError, match="`config` must be the object of the run it was made from"):
        gate.load_baseline(p)  # a null config would skip the comparability check


@pytest.mark.parametrize("fmt", [0, 3, 99])
def test_other_formats_are_refused_in_one_line(tmp_path, fmt):
    p = tmp_path / "b.json"
    p.write_text(json.dumps({"format": fmt, "metrics": {}}))
    with pytest.raises(ValueError, match=rf"is format {fmt}: this stripebench reads baseline formats 1 and 2") as e:
        gate.load_baseline(p)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("fmt", [True, 1.0, "1"])
def test_a_format_that_is_not_an_integer_is_refused(fmt):
    with pytest.raises(ValueError, match="is not a stripebench baseline"):
        gate.validate_baseline({"format": fmt, "metrics": {}})


def test_bad_renderer_and_tolerance_source_are_named():
    with pytest.raises(ValueError, match="`renderer` must be a string"):
        gate.validate_baseline({"format": 2, "metrics": {}, "renderer": 3})
    with pytest.raises(ValueError, match="`tolerance_source` must be a string or an object with a `procedure`"):
        gate.validate_baseline({"format": 2, "metrics": {}, "tolerance_source": {"safety": 2}})


def test_renderer_difference_only_when_both_are_known():
    assert gate.renderer_difference({"renderer": "a"}, {"renderer": "a"}) == ""
    assert gate.renderer_difference({}, {"renderer": "a"}) == ""
    assert gate.renderer_difference({"renderer": "a"}, {"renderer": "b"}) == "renderer ('a' vs 'b')"


@pytest.mark.slow
def test_check_refuses_a_baseline_rendered_otherwise_and_a_newer_format(gate_run, tmp_path, capsys):
    out, base = gate_run
    doc = json.loads(base.read_text())
    assert doc["format"] == gate.FORMAT and doc["renderer"].startswith(doc["variants"][0])
    other = tmp_path / "other.json"
    other.write_text(json.dumps({**doc, "renderer": "scalar_rgb"}))
    assert main(["check", str(out), "--baseline", str(other)]) == 2
    err = capsys.readouterr().err.strip()
    assert "not comparable: their frames were rendered differently, renderer (" in err and "\n" not in err
    newer = tmp_path / "newer.json"
    newer.write_text(json.dumps({**doc, "format": gate.FORMAT + 1}))
    assert main(["check", str(out), "--baseline", str(newer)]) == 2
    assert f"is format {gate.FORMAT + 1}" in capsys.readouterr().err


@pytest.mark.slow
def test_update_keeps_derived_tolerances_and_their_source(gate_run, tmp_path):
    out, _ = gate_run
    p = tmp_path / "b.json"
    tols = {m: {"direction": d, "abs": a * 3, "rel": r} for m, (d, a, r) in gate.TOLERANCES.items()}
    source = {"procedure": "stripebench spread", "safety": 2.0}
    gate.write_baseline(out, p, tolerances=tols, tolerance_source=source)
    assert main(["check", str(out), "--baseline", str(p), "--update"]) == 0
    doc = gate.load_baseline(p)
    assert doc["tolerances"] == tols and doc["tolerance_source"] == source
    plain = tmp_path / "plain.json"
    gate.write_baseline(out, plain)
    assert gate.load_baseline(plain)["tolerance_source"] == "defaults"


@pytest.mark.slow
def test_reuse_reads_finished_runs_without_running_them(gate_run, tmp_path, monkeypatch):
    import shutil

    out, _ = gate_run
    shutil.copytree(out, tmp_path / "ci-here")
    monkeypatch.setattr(gs, "_run_one", lambda *a, **kw: pytest.fail("ran"))
    here = next(m for m in gs.MACHINES if m.name == gs.REFERENCE)
    docs = gs.measure(tmp_path, gates=["ci"], machines=[here], reuse=True, log=lambda s: None)
    assert docs["ci"]["here"]["wall_s"] is None
    assert docs["ci"]["here"]["metrics"] == gate.baseline_from_run(out)["metrics"]


def test_ci_runs_the_gates_as_the_procedure_measured_them():
    ci = (Path(__file__).resolve().parents[3] / ".ci" / "run").read_text()
    assert f"--trackers {gs.REAL_TRACKERS}" in ci.replace("\\\n    ", "")
    # the README's commands as written: the ci profile asks for the target the procedure measured with
    from bench.config import profile

    assert "export STRIPEBENCH_LLVM_TARGET" not in ci and "unset STRIPEBENCH_LLVM_TARGET" in ci
    assert gs.GATE_ENV == {"STRIPEBENCH_LLVM_TARGET": profile("ci").llvm_target} == {
        "STRIPEBENCH_LLVM_TARGET": "portable"}


# -- another real machine: entry tolerances ------------------------------------------------

def test_entry_tolerances_cover_only_the_entries_another_machine_moves():
    tols = gs.derive_tolerances({}, gate.TOLERANCES)
    here = _doc({"a/t/all": {"px_mae": 1.0, "hit_rate": 0.9}, "b/t/all": {"px_mae": 1.0, "hit_rate": 0.9}})
    there = _doc({"a/t/all": {"px_mae": 1.01, "hit_rate": 0.9}, "b/t/all": {"px_mae": 1.4, "hit_rate": 0.87}})
    entry = gs.derive_entry_tolerances(gs.entry_ranges({"here": here, "there": there}), tols)
    assert set(entry) == {"b/t/all"} and set(entry["b/t/all"]) == {"px_mae", "hit_rate"}
    base = {**here, "tolerances": tols, "entry_tolerances": entry}
    assert not any(r.failed for r in gate.compare(base, there))  # the other machine passes
    worse = _doc({"a/t/all": {"px_mae": 1.2, "hit_rate": 0.9}, "b/t/all": {"px_mae": 1.4, "hit_rate": 0.9}})
    failed = [(r.key, r.metric) for r in gate.compare(base, worse) if r.failed]
    assert failed == [("a/t/all", "px_mae")]  # an entry no machine moved keeps its metric's tolerance
    with pytest.raises(ValueError, match="`safety` must be a number >= 1"):
        gs.derive_entry_tolerances({}, tols, safety=0.5)


@pytest.mark.parametrize("bad, message", [
    ([1], "`entry_tolerances` must be an object"),
    ({"e/t/all": {"px_mae": {"abs": 0.1}}}, "`entry_tolerances.e/t/all.px_mae` must have exactly `abs` and `rel`"),
    ({"e/t/all": {"px_mae": {"abs": -1, "rel": 0}}}, "`entry_tolerances.e/t/all.px_mae.abs` must be a number >= 0"),
])
def test_bad_entry_tolerances_are_named(bad, message):
    doc = {"format": 2, "metrics": {"e/t/all": {"px_mae": 1.0}}, "config": {}, "entry_tolerances": bad}
    with pytest.raises(ValueError, match=message.replace(".", r"\.")):
        gate.validate_baseline(doc)


def test_against_needs_one_gate_and_a_readable_baseline(tmp_path, capsys):
    assert gs.study(out=tmp_path, against=[tmp_path / "x.json"]) == 2
    assert capsys.readouterr().err.strip() == ("gate_spread: `--against` compares baselines of one gate: name it "
                                               "with `--gates`, got 'ci,real'")
    assert main(["spread", "--out", str(tmp_path), "--gates", "ci", "--against", str(tmp_path / "x.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"gate_spread: `--against` '{tmp_path / 'x.json'}':")


def test_update_keeps_entry_tolerances(gate_run, tmp_path):
    out, _ = gate_run
    p = tmp_path / "b.json"
    tols = {m: {"direction": d, "abs": a, "rel": r} for m, (d, a, r) in gate.TOLERANCES.items()}
    key = next(iter(gate.baseline_from_run(out)["metrics"]))
    entry = {key: {"px_mae": {"abs": 0.5, "rel": 0.05}}}
    gate.write_baseline(out, p, tolerances=tols, tolerance_source={"procedure": "stripebench spread"},
                        entry_tolerances=entry)
    assert main(["check", str(out), "--baseline", str(p), "--update"]) == 0
    assert gate.load_baseline(p)["entry_tolerances"] == entry
