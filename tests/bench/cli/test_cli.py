"""The command tree and ``main`` (bench/cli/__init__.py): one parser, one-line errors, plain help,
every documented bad input with its test."""

import re
import subprocess
import sys

import pytest

from bench.cli import build_parser, main
from cli_helpers import REPO, one_line_err


def test_bad_seed_is_a_usage_error():
    out = subprocess.run([sys.executable, "-m", "bench.cli", "reproduce", "--seed", "-1"], capture_output=True,
                         text=True)
    assert out.returncode == 2 and "--seed: must be an integer >= 0 (at most 2**63 - 1), got '-1'" in out.stderr


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.startswith("stripebench 0.")


def test_argparse_errors_are_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--bogus"])
    assert exc.value.code == 2
    one_line_err(capsys, "unrecognized arguments: --bogus")
    with pytest.raises(SystemExit):
        main(["reproduce", "--profile", "nope"])
    one_line_err(capsys, "invalid choice: 'nope'")


@pytest.mark.parametrize("argv", [["estimators", "-h"], ["perf", "scenes", "-h"], ["perf", "-h"], ["tune", "-h"], ["translucency", "-h"], ["trackers", "-h"], ["-h"]])
def test_help_is_plain_text(argv, capsys):
    with pytest.raises(SystemExit):
        main(argv)
    out = capsys.readouterr().out
    assert "``" not in out and ":func:" not in out and "python -m" not in out


def test_every_command_and_sub_command_has_plain_help():
    from bench.cli import command_groups

    names = [[c.name] for _, cs in command_groups() for c in cs]
    names += [["perf", c.name] for c in dict((c.name, c) for _, cs in command_groups() for c in cs)["perf"].subcommands]
    for argv in names:
        parser = build_parser()
        with pytest.raises(SystemExit) as exc:
            parser.parse_args([*argv, "-h"])
        assert exc.value.code == 0


def test_docs_errors_names_tests_that_exist():
    """Every ``test_module.py::test_name`` (or a prefix ending in ``...``) in docs/errors.md is a test."""
    doc = (REPO / "docs" / "errors.md").read_text()
    refs = re.findall(r"`(?:[a-z]+/)?(test_\w+\.py)::(test_\w+?)(?:_?\.\.\.)?`", doc)
    assert len(refs) > 20
    sources = {p.name: [] for p in (REPO / "tests").rglob("test_*.py")}
    for p in (REPO / "tests").rglob("test_*.py"):
        sources[p.name].append(p.read_text())
    for module, name in refs:
        assert module in sources, module
        assert any(re.search(rf"^def {name}", s, re.M) for s in sources[module]), f"{module}::{name}"


@pytest.mark.parametrize("setting, message", [
    ('{label="g",name="threshold",restore="fill"}', "`--trackers[0].restore` must be one of 'rows', 'none', got 'fill'"),
    ('{label="g",name="nope",restore="none"}', "`--trackers[0]` names unknown tracker 'nope'"),
])
def test_a_bad_setting_restore_is_one_line_and_status_2(setting, message, capsys):
    with pytest.raises(SystemExit) as exc:  # a typed option: argparse's one line
        main(["reproduce", "--trackers", setting])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and err[0].startswith("stripebench: error:")


def test_docs_config_names_every_key_of_the_schema():
    from dataclasses import fields

    from bench import config
    from bench.config.tune import TOP_KEYS, TUNE_RENDER_KEYS

    doc = (REPO / "docs" / "config.md").read_text()
    keys = {f.name for f in fields(config.Config)} - {"source", "tracker_specs"}
    keys |= {f"render.{k}" for k in ("width", "height")} | {"render.spp", "render.ambient_spp"}
    keys |= {f"experiments[i].{f.name}" for f in fields(config.Experiment)} - {"experiments[i].overrides",
                                                                               "experiments[i].angles"}
    for k in sorted(keys):
        assert f"`{k}`" in doc or f"`{k.split('.')[-1]}`" in doc, k
    for k in (*TOP_KEYS, *TUNE_RENDER_KEYS, "repeats"):
        assert f"`{k}`" in doc or k in doc, k


def test_the_module_docstring_lists_every_command():
    """The command list in bench.cli's docstring is checked against the command tree (issue 36's drift list)."""
    import re

    import bench.cli as cli
    from bench.cli.perf import PERF

    doc = " ".join(cli.__doc__.split())
    for group, commands in cli.command_groups():
        listed = re.search(rf"``{group}``(: ([^;]*))?", doc)
        assert listed, f"group {group!r} missing from bench.cli's docstring"
        names = [c.name for c in commands]
        if names != [group]:
            assert listed.group(2) is not None and all(n in listed.group(2) for n in names), (group, names)
    perf = re.search(r"perf \{([^}]*)\}", doc).group(1)
    assert [s.strip() for s in perf.split(",")] == [c.name for c in PERF]


def test_every_error_line_is_bounded(capsys):
    """A message that quotes a whole input (here a 1 MB option value) is cut to bench.errors.LINE_CHARS."""
    from bench.cli import main
    from bench.errors import LINE_CHARS

    with pytest.raises(SystemExit) as exit:  # an argparse error
        main(["track", "nothing.png", "--out", "/tmp/never-made", "--trackers", "t" * 2**20])
    code, err = exit.value.code, capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and len(err) < LINE_CHARS + 100 and "characters)" in err


def test_an_error_raised_after_parsing_is_bounded_too(tmp_path, capsys):
    from bench.cli import main
    from bench.errors import LINE_CHARS

    cfg = tmp_path / "c.toml"
    cfg.write_text(f'name = "{"n" * 2**20}"\n')
    assert main(["run", str(cfg), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and len(err) < LINE_CHARS + 100
