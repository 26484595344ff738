"""The study commands in the tree (bench/cli/studies.py): estimators, translucency, tune, perf {...}."""

import subprocess
import sys

import pytest

from bench.cli import build_parser, main
from cli_helpers import REPO, cli, one_line, one_line_err, status


@pytest.mark.parametrize("value, message", [
    ("nan", "argument --sigmas: must be a finite number > 0, got 'nan'"),
    ("-1", "argument --sigmas: must be a finite number > 0, got '-1'"),
    ("1,inf", "got 'inf' (in '1,inf')"),
    ("1,1", "argument --sigmas: repeats a value"),
])
def test_estimators_sigmas_must_be_finite_and_positive(tmp_path, value, message):
    one_line(cli("estimators", "--sigmas", value, "--out", tmp_path / "o"), message)
    assert not (tmp_path / "o").exists()


def test_estimators_runs_in_the_tree_and_writes_its_table(tmp_path, capsys):
    out = tmp_path / "e"
    assert main(["estimators", "--sigmas", "1.0", "--peaks", "50", "--noises", "1", "--frames", "1",
                 "--trackers", "gauss3", "--no-plot", "--out", str(out)]) == 0
    assert (out / "estimators.csv").read_text().count("\n") == 2  # header + one cell
    assert status(["estimators", "--trackers", "threshold", "--out", str(out)]) == 2
    one_line_err(capsys, "none of the selected trackers is a sub-pixel tracker")
    assert status(["estimators", "--trackers", '{label="g",name="gauss3"}', "--out", str(out)]) == 2
    one_line_err(capsys, "give plain names")


def test_the_python_m_entry_points_are_built_from_the_same_options():
    def options(argv):
        out = subprocess.run([sys.executable, *argv, "-h"], capture_output=True, text=True, cwd=REPO, check=True).stdout
        return sorted(w for w in out.split() if w.startswith("--"))

    assert options(["-m", "bench.cli.gate_spread"]) == options(["-m", "bench.cli", "spread"])
    assert "--single-scatter" in options(["-m", "bench.cli.translucency_profile"])
    assert options(["-m", "bench.cli.field_sheet"]) == ["--cost", "--help"]


def _study_commands():
    from bench.cli import command_groups
    from bench.cli.studies import FIELD_SHEET, TRANSLUCENCY_PROFILE

    out = [FIELD_SHEET, TRANSLUCENCY_PROFILE]
    for _, commands in command_groups():
        for c in commands:
            out += [c, *c.subcommands]
    return [c for c in out if c.calls]


def test_every_option_of_a_study_command_is_a_parameter_of_its_plain_function():
    import importlib
    import inspect

    from bench.cli.common import options_of

    commands = _study_commands()
    assert {c.name for c in commands} >= {"estimators", "translucency", "spread", "trackers", "sampling", "mis",
                                          "field_sheet", "translucency_profile"}
    for c in commands:
        module, _, function = c.calls.partition(":")
        params = inspect.signature(getattr(importlib.import_module(module), function)).parameters
        assert all(p.kind == p.KEYWORD_ONLY or p.name == "out" for p in params.values()), c.calls
        missing = [d for d in options_of(c.add_arguments) if d not in params]
        assert not missing, (c.calls, missing)


def test_every_tune_procedure_takes_the_tune_options():
    import importlib
    import inspect

    from bench.cli.common import options_of
    from bench.cli.tune import COMMAND, PROCEDURES

    for module in PROCEDURES.values():
        params = inspect.signature(importlib.import_module(module).study).parameters
        assert [d for d in options_of(COMMAND.add_arguments) if d != "what"] == [p for p in params], module


def test_perf_alone_is_perf_trackers_and_its_sub_commands_parse():
    parser = build_parser()
    alone = parser.parse_args(["perf"])
    assert alone.perf_command is None and alone.func.__name__ == "run_default"
    for what, option in (("trackers", "--strict"), ("scenes", "--frames=0"), ("sweep", "--trials=1"),
                         ("shiny", "--cost"), ("sampling", "--angles=1"), ("scenes", "--strict")):
        args = build_parser().parse_args(["perf", what, option])
        assert args.perf_command == what
    with pytest.raises(SystemExit):
        build_parser().parse_args(["perf", "--scenes"])  # no longer an option


def test_perf_strict_alone_runs_perf_trackers_strict(monkeypatch):
    import bench.studies.perf.trackers as T

    seen = {}
    monkeypatch.setattr(T, "study", lambda strict=False, **kw: seen.setdefault("strict", strict) and 0)
    for argv, strict in ((["perf", "--strict"], True), (["perf"], False)):
        seen.clear()
        args = build_parser().parse_args(argv)
        args.func(args)
        assert seen == {"strict": strict}


def test_perf_trackers_bad_frames_are_one_line(tmp_path):
    bad = tmp_path / "x.npy"
    bad.write_bytes(b"not an array")
    one_line(cli("perf", "trackers", "--frames", bad, "--no-jit"), "--frames: cannot read", "x.npy")
    one_line(cli("perf", "trackers", "--repeats", "0"), "argument --repeats: must be an integer 1 .. 1000")


def test_translucency_bad_options_are_one_line(tmp_path):
    one_line(cli("translucency", "--materials", "velvet", "--out", tmp_path), "unknown material 'velvet'")
    one_line(cli("translucency", "--size", "100", "--out", tmp_path), "argument --size: must be a multiple of 16")
    one_line(cli("translucency", "--trackers", "threshold", "--out", tmp_path), "none of the selected trackers")


def test_tune_bad_profiles_are_one_line_before_any_scan(tmp_path):
    from bench.config.tune import DEFAULT_PROFILE

    bad = tmp_path / "p.toml"
    bad.write_text(DEFAULT_PROFILE.read_text().replace('scene = "sphere"', 'scene = "teapot"', 1))
    one_line(cli("tune", "dp", "--profile", bad, "--out", tmp_path / "o"), "`experiments[0].scene` must be one of")
    bad.write_text(DEFAULT_PROFILE.read_text().replace("hit_px = 3.0", "hit_px = nan"))
    one_line(cli("tune", "dp", "--profile", bad, "--out", tmp_path / "o"), "`hit_px` must be a finite number >= 0")
    one_line(cli("tune", "dp", "--profile", tmp_path / "nope.toml"), "cannot read tuning profile", "no such file")
    assert not (tmp_path / "o").exists()
