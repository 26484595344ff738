"""``stripebench reproduce``, ``run``, ``report``, ``check``, ``compare`` (bench/cli/run.py)."""

import json
import os
import time
from pathlib import Path

import pytest

from bench.cli import main
from cli_helpers import TOML, cli, one_line, one_line_err


@pytest.mark.parametrize(
    "argv, message",
    [
        (["run"], "give a CONFIG.toml or --profile"),
        (["run", "missing.toml"], "cannot read configuration 'missing.toml'"),
        (["report", "not-a-run"], "RUN must be a finished run folder"),
    ],
)
def test_bad_values_give_one_line_and_status_2(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0] and err[0].startswith("stripebench: error:")


def test_bad_config_file_names_the_key(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(TOML.replace("n_samples = 5", "n_samples = -5"))
    assert main(["run", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == "stripebench: error: `n_samples` must be an integer >= 1, got -5"


@pytest.mark.slow
def test_run_a_config_file_then_rebuild_its_report(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML)
    out_dir = tmp_path / "run"
    assert main(["run", str(cfg), "--out", str(out_dir), "--quiet"]) == 0
    assert f"report at {out_dir / 'report.html'}" in capsys.readouterr().out
    (out_dir / "report.html").unlink()
    assert main(["report", str(out_dir), "--quiet"]) == 0
    assert (out_dir / "report.html").is_file()


@pytest.mark.parametrize(
    "change, message",
    [
        (("n_angles = 2", "angles = [0.0, nan]"), "`experiments[0].angles` must be finite"),
        (("n_angles = 2", "angles = [0.0, inf]"), "`experiments[0].angles` must be finite"),
        (("n_angles = 2", "angles = [0.0, 1e30]"), "within +-45 deg"),
        (("n_angles = 2", "n_angles = 1000000000"), "`experiments[0].n_angles` must be at most"),
        (("n_angles = 2", "n_angles = 2\nlaser_power_mw = 1e30"), "`experiments[0].laser_power_mw` must be at most"),
        (("n_angles = 2", "n_angles = 2\nambient_lux = nan"), "`ambient_lux` must be a finite number"),
        (("n_angles = 2", "n_angles = 2\nf_number = 1e-6"), "`experiments[0].f_number` must be at least 0.5"),
        (("n_angles = 2", "n_angles = 2\nline_fwhm_mrad = 1e-9"), "`experiments[0].line_fwhm_mrad` must be at least"),
        (("spp = 1", "spp = 1000000000"), "`render.spp` must be at most 65536"),
        (("width = 64", "width = 1000000"), "`render.width` must be at most 8192"),
        (("[[experiments]]", "[[experiments]]\nangles = [0.0, 1.0]", "n_angles = 2", "n_angles = 100000",
          "width = 64", "width = 8192", "height = 60", "height = 7680", "angles = [0.0, 1.0]\n", ""),
         "GiB of memory"),
        (("n_boot = 20", "n_boot = 1e9"), "`n_boot` must be an integer"),
        (("name = \"cli\"", "name = \"cli\"\nbogus = 1"), "unknown key `bogus`"),
    ],
)
def test_ranges_that_break_the_renderer_or_memory_are_refused_before_any_work(change, message, tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    text = TOML
    for old, new in zip(change[::2], change[1::2]):
        text = text.replace(old, new)
    cfg.write_text(text)
    t0 = time.monotonic()
    assert main(["run", str(cfg), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    one_line_err(capsys, message)
    assert time.monotonic() - t0 < 20 and not (tmp_path / "out").exists()


def test_spp_times_pixels_beyond_mitsubas_count_is_refused(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML.replace("width = 64", "width = 8192").replace("height = 60", "height = 7680")
                   .replace("spp = 1\n", "spp = 100\n"))
    assert main(["run", str(cfg), "--out", str(tmp_path / "out")]) == 2
    one_line_err(capsys, "2**32 - 1 samples")


@pytest.mark.slow
def test_out_problems_are_one_line_with_the_path(cli_run, tmp_path, capsys, monkeypatch):
    run_dir, cfg = cli_run
    capsys.readouterr()
    f = tmp_path / "afile"
    f.write_text("x")
    assert main(["run", str(cfg), "--out", str(f), "--quiet"]) == 2
    one_line_err(capsys, "--out must be a folder", "afile")
    assert main(["run", str(cfg), "--out", str(f / "sub"), "--quiet"]) == 2
    one_line_err(capsys, "afile")
    assert main(["run", str(cfg), "--out", "/sys/stripebench-readonly-test", "--quiet"]) == 2
    one_line_err(capsys, "cannot create run folder", "/sys/stripebench-readonly-test")
    # another configuration into the same folder
    other = tmp_path / "other.toml"
    other.write_text(TOML.replace("seed = 0", "seed = 1"))
    assert main(["run", str(other), "--out", str(run_dir), "--quiet"]) == 2
    one_line_err(capsys, "holds a run of another configuration", "--force")


@pytest.mark.slow
def test_a_full_disk_is_one_line(cli_run, tmp_path, capsys, monkeypatch):
    import errno

    from bench.store import runfolder

    def full(path, data):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(runfolder, "atomic_write_bytes", full)
    monkeypatch.setattr(runfolder, "atomic_write_text", lambda p, t: full(p, t))
    assert main(["run", str(cli_run[1]), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    one_line_err(capsys, "no space left on the device", str(tmp_path / "o"))


@pytest.mark.parametrize("var", ["STRIPEBENCH_RUNS", "STRIPEBENCH_CACHE_DIR"])
def test_environment_variables_naming_a_file_are_one_line(var, tmp_path, capsys, monkeypatch):
    f = tmp_path / "afile"
    f.write_text("x")
    monkeypatch.setenv(var, str(f))
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML)
    assert main(["run", str(cfg), "--quiet"]) == 2
    one_line_err(capsys, f"${var} must name a folder", "afile")


def test_a_malformed_llvm_target_is_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("STRIPEBENCH_LLVM_TARGET", "haswell/6")
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML)
    assert main(["run", str(cfg), "--quiet"]) == 2
    one_line_err(capsys, "`STRIPEBENCH_LLVM_TARGET` must be", "'haswell/6'")


@pytest.mark.slow
@pytest.mark.parametrize(
    "doc, message",
    [
        ("null", "is not a stripebench baseline"),
        ('"a string"', "is not a stripebench baseline"),
        ('{"format": 1, "metrics": null}', "`metrics` must be an object"),
        ('{"format": 1, "metrics": {"a/b/all": {"px_mae": "x"}}}', "must be a number or null"),
        ('{"format": 1, "metrics": {}, "tolerances": {"px_mae": {"direction": "lower", "rel": 0.1}}}',
         "must have exactly `direction`, `abs` and `rel`"),
        ('{"format": 1, "metrics": {}, "tolerances": {"px_mae": {"direction": "up", "abs": 0, "rel": 0}}}',
         "'lower' or 'higher'"),
        ("{nope", "is not valid JSON"),
    ],
)
def test_malformed_baselines_are_one_line(doc, message, cli_run, tmp_path, capsys):
    base = tmp_path / "b.json"
    base.write_text(doc)
    assert main(["check", str(cli_run[0]), "--baseline", str(base)]) == 2
    one_line_err(capsys, message)


@pytest.mark.slow
def test_corrupt_run_files_in_report_check_and_compare_are_one_line(cli_run, tmp_path, capsys):
    import shutil

    run_dir = tmp_path / "copy"
    shutil.copytree(cli_run[0], run_dir)
    (run_dir / "metrics.parquet").write_bytes(b"PAR1 garbage")
    base = tmp_path / "b.json"
    assert main(["check", str(run_dir), "--baseline", str(base), "--update"]) == 2
    one_line_err(capsys, "metrics.parquet")
    assert main(["compare", str(cli_run[0]), str(run_dir)]) == 2
    one_line_err(capsys, "metrics.parquet")
    (run_dir / "summary.json").write_text("{")
    assert main(["report", str(run_dir), "--quiet"]) == 2
    one_line_err(capsys, "summary.json", "is not valid JSON")


@pytest.mark.slow
def test_check_and_compare_refuse_runs_of_another_resolution(cli_run, tmp_path, capsys):
    run_dir, cfg = cli_run
    big = tmp_path / "big.toml"
    big.write_text(TOML.replace("width = 64", "width = 128").replace("height = 60", "height = 120"))
    other = tmp_path / "other"
    assert main(["run", str(big), "--out", str(other), "--quiet", "--no-report"]) == 0
    capsys.readouterr()
    assert main(["compare", str(run_dir), str(other)]) == 2
    one_line_err(capsys, "are not comparable", "render", "compared: render, experiments, seed")
    base = tmp_path / "base.json"
    assert main(["check", str(run_dir), "--baseline", str(base), "--update"]) == 0
    capsys.readouterr()
    assert main(["check", str(other), "--baseline", str(base)]) == 2
    one_line_err(capsys, "are not comparable")


@pytest.mark.slow
def test_compare_across_sampling_allows_only_other_sample_counts(cli_run, tmp_path, capsys):
    run_dir, cfg = cli_run
    more = tmp_path / "more.toml"
    more.write_text(TOML.replace("spp = 1\nambient_spp = 1", 'spp = 2\nambient_spp = "auto"'))
    other = tmp_path / "other"
    assert main(["run", str(more), "--out", str(other), "--quiet", "--no-report"]) == 0
    capsys.readouterr()
    assert main(["compare", str(run_dir), str(other)]) == 2
    one_line_err(capsys, "are not comparable", "render", "compared:")
    assert main(["compare", str(run_dir), str(other), "--across-sampling"]) in (0, 1)
    out = capsys.readouterr().out
    assert "checks:" in out and f"{other} against {run_dir}" in out
    big = tmp_path / "big.toml"
    big.write_text(TOML.replace("width = 64", "width = 128").replace("height = 60", "height = 120"))
    wide = tmp_path / "wide"
    assert main(["run", str(big), "--out", str(wide), "--quiet", "--no-report"]) == 0
    capsys.readouterr()
    assert main(["compare", str(run_dir), str(wide), "--across-sampling"]) == 2
    one_line_err(capsys, "are not comparable", "render")


@pytest.mark.slow
def test_compare_two_runs_of_the_same_configuration(cli_run, tmp_path, capsys):
    run_dir, cfg = cli_run
    again = tmp_path / "again"
    assert main(["run", str(cfg), "--out", str(again), "--quiet", "--no-report"]) == 0
    capsys.readouterr()
    assert main(["compare", str(run_dir), str(again)]) == 0
    assert "0 failed" in capsys.readouterr().out
    assert main(["compare", str(run_dir), str(again), "--json", "--all"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["failed"] == 0 and doc["checks"] == len(doc["rows"]) > 0
    assert {r["verdict"] for r in doc["rows"]} == {"ok"}
    base = tmp_path / "b.json"
    assert main(["check", str(run_dir), "--baseline", str(base), "--update"]) == 0
    capsys.readouterr()
    assert main(["check", str(again), "--baseline", str(base), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["failed"] == 0 and doc["rows"] == []


def test_run_help_points_to_the_config_reference(capsys):
    with pytest.raises(SystemExit):
        main(["run", "-h"])
    out = capsys.readouterr().out
    assert "docs/config.md" in out
    assert (Path(__file__).resolve().parents[3] / "docs" / "config.md").is_file()


# -- stripebench sweep -------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_no_render_ahead_turns_the_helper_off_and_resumes_the_same_run_folder(cli_run, capsys):
    """``--no-render-ahead`` on two experiments: no helper; the flag is not part of the run's identity,
    so it resumes (does not refuse) the folder of the same configuration run with the helper on."""
    run_dir, _ = cli_run
    cfg = run_dir.parent / "two.toml"
    cfg.write_text(TOML + '[[experiments]]\nscene = "cone"\nmaterial = "patchy"\nn_angles = 2\n')
    out = run_dir.parent / "two"
    assert main(["run", str(cfg), "--out", str(out), "--quiet", "--no-report", "--no-render-ahead"]) == 0
    assert json.loads((out / "summary.json").read_text())["render_ahead"] == {"off": "turned off"}
    assert main(["run", str(cfg), "--out", str(out), "--quiet", "--no-report"]) == 0
    ra = json.loads((out / "summary.json").read_text())["render_ahead"]
    assert ra["started"] is False and ra["frames"] == 4  # resumed: every frame was done, no helper needed


# -- bad inputs found by probes: one line, exit 2, before any work (subprocess, as a user sees them) --------------

def test_trackers_naming_an_unknown_tracker_or_nothing_is_one_line(config_file):
    one_line(cli("run", config_file, "--trackers", "nope"), "--trackers", "names unknown tracker 'nope'")
    one_line(cli("run", config_file, "--trackers", ","), "argument --trackers: must name at least one tracker")
    one_line(cli("run", config_file, "--trackers", "{" * 5000), "--trackers")


def test_a_configuration_that_is_not_utf8_is_one_line(tmp_path):
    bad = tmp_path / "latin1.toml"
    bad.write_bytes(TOML.replace('name = "cli"', 'name = "caf\xe9"').encode("latin-1"))
    one_line(cli("run", bad), "is not UTF-8 text", "latin1.toml")


@pytest.mark.parametrize("nested", ["a = " + "[" * 5000 + "]" * 5000, "a = " + "{b = " * 3000 + "1" + "}" * 3000,
                                    "a = [" + "[" * 100 + "]" * 100 + "]"])
def test_a_deeply_nested_configuration_is_one_line(tmp_path, nested):
    bad = tmp_path / "deep.toml"
    bad.write_text(nested + "\n" + TOML)
    one_line(cli("run", bad), "nested too deeply", "deep.toml")


def test_a_huge_integer_in_a_configuration_is_one_line(tmp_path):
    bad = tmp_path / "big.toml"
    bad.write_text(TOML.replace("seed = 0", "seed = 1" + "0" * 400))
    one_line(cli("run", bad), "integer of 401 digits")


def test_a_fifo_given_as_configuration_is_refused_without_waiting(tmp_path):
    fifo = tmp_path / "c.toml"
    os.mkfifo(fifo)
    t0 = time.monotonic()
    one_line(cli("run", fifo, timeout=60), "is not a regular file (a FIFO)")
    one_line(cli("run", tmp_path, timeout=60), "is not a regular file (a folder)")
    assert time.monotonic() - t0 < 60


def test_a_real_set_without_manifest_is_refused_before_any_scan(tmp_path):
    (tmp_path / "notaset").mkdir()
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML.replace('name = "cli"', f'name = "cli"\nreal_set = "{tmp_path / "notaset"}"'))
    t0 = time.monotonic()
    one_line(cli("run", cfg, "--out", tmp_path / "out"), "`real_set`", "no manifest.csv")
    assert not (tmp_path / "out").exists() and time.monotonic() - t0 < 60


def test_a_broken_real_set_is_refused_before_any_scan(tmp_path, capsys):
    import shutil

    from bench.store.realset import SHIPPED

    broken = tmp_path / "broken"
    shutil.copytree(SHIPPED, broken)
    next(broken.glob("*_ref.csv")).write_bytes(b"row,col\n0,\xff\n")
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML.replace('name = "cli"', f'name = "cli"\nreal_set = "{broken}"'))
    assert main(["run", str(cfg), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    one_line_err(capsys, "`real_set`", "is not a valid real set", "not UTF-8")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("value", ["garbage", "llvm_ad_spectral"])
def test_a_bad_mitsuba_variant_is_one_line_before_any_work(config_file, tmp_path, value):
    proc = cli("run", config_file, "--out", tmp_path / "out", env={"STRIPEBENCH_VARIANT": value})
    one_line(proc, "$STRIPEBENCH_VARIANT", repr(value), "usable here:")
    assert not (tmp_path / "out").exists()


def test_a_cuda_variant_without_a_gpu_is_one_line(config_file, tmp_path):
    import drjit as dr

    if dr.has_backend(dr.JitBackend.CUDA):
        pytest.skip("this machine has a CUDA backend")
    proc = cli("run", config_file, "--out", tmp_path / "out", env={"STRIPEBENCH_VARIANT": "cuda_ad_mono"})
    one_line(proc, "'cuda_ad_mono' needs a CUDA GPU and driver")


@pytest.mark.slow
def test_report_check_and_compare_on_damaged_run_files_are_one_line(cli_run, tmp_path):
    import shutil

    import pandas as pd

    run_dir = cli_run[0]
    summary = json.loads((run_dir / "summary.json").read_text())
    for key in ("git_revision", "versions", "variants", "wall_s", "paper_improvement"):
        d = tmp_path / f"no-{key}"
        shutil.copytree(run_dir, d)
        (d / "summary.json").write_text(json.dumps({k: v for k, v in summary.items() if k != key}))
        one_line(cli("report", d, "--quiet"), f"`{key}` missing")
    metrics = pd.read_parquet(run_dir / "metrics.parquet")
    for column in ("hit_rate", "coverage"):
        d = tmp_path / f"no-{column}"
        shutil.copytree(run_dir, d)
        metrics.drop(columns=[column]).to_parquet(d / "metrics.parquet", index=False)
        one_line(cli("report", d, "--quiet"), f"no column {column!r}")
    deep = tmp_path / "deep"
    shutil.copytree(run_dir, deep)
    (deep / "summary.json").write_text("[" * 100000 + "]" * 100000)
    one_line(cli("report", deep, "--quiet"), "summary.json", "nested too deeply")
    one_line(cli("compare", run_dir, deep), "summary.json", "nested too deeply")


@pytest.mark.slow
@pytest.mark.parametrize("doc, message", [
    ("[" * 100000 + "]" * 100000, "nested too deeply"),
    ('{"format": 1, "metrics": {"a/b/all": {"px_mae": 1' + "0" * 400 + "}}}", "integer of 401 digits"),
])
def test_deep_or_huge_baselines_are_one_line(cli_run, tmp_path, doc, message):
    base = tmp_path / "b.json"
    base.write_text(doc)
    one_line(cli("check", cli_run[0], "--baseline", base), "baseline", message)
    os.mkfifo(tmp_path / "fifo.json")
    one_line(cli("check", cli_run[0], "--baseline", tmp_path / "fifo.json", timeout=60), "not a regular file")


def test_same_config_and_seed_give_byte_identical_metrics(tmp_path, config_file):
    """The determinism rule, through the command line: two runs, byte-identical metrics.csv and samples.csv."""
    a, b = tmp_path / "a", tmp_path / "b"
    assert main(["run", str(config_file), "--out", str(a), "--quiet", "--no-report"]) == 0
    assert main(["run", str(config_file), "--out", str(b), "--quiet", "--no-report", "--no-render-ahead"]) == 0
    for name in ("metrics.csv", "samples.csv"):
        assert (a / name).read_bytes() == (b / name).read_bytes()


def test_a_full_disk_during_the_report_names_the_figure(tiny_run, tmp_path, capsys, monkeypatch):
    """Issue 37 item 7: matplotlib writes through a file object, so its OSError named no file."""
    import errno
    import shutil

    from matplotlib.figure import Figure

    from bench.report import runfigures

    run_dir = tmp_path / "run"
    shutil.copytree(tiny_run[0], run_dir)

    def full(self, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")  # as from a write on an open file: no filename

    monkeypatch.setattr(Figure, "savefig", full)
    monkeypatch.setattr(runfigures, "figure_workers", lambda n, workers=None: 0)  # drawn here, where the patch is
    assert main(["report", str(run_dir), "--quiet"]) == 2
    one_line_err(capsys, "no space left on the device", str(run_dir / "figures"), ".png")


def test_a_run_prints_its_headline_with_the_verdicts(tiny_run, tmp_path, capsys, monkeypatch):
    """`reproduce` / `run` end with the paper's claim per reading, as the report's headline gives it."""
    import shutil

    from bench.evaluate.readings import claims_of
    from bench.run import experiment
    from cli_helpers import TOML

    out, _ = tiny_run
    copy = tmp_path / "done"
    shutil.copytree(out, copy)
    monkeypatch.setattr(experiment, "run", lambda *a, **k: copy)  # the run itself: the finished tiny run
    cfg = tmp_path / "c.toml"
    cfg.write_text(TOML)
    assert main(["run", str(cfg), "--out", str(tmp_path / "new"), "--no-report", "--quiet"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    summary = json.loads((copy / "summary.json").read_text())
    claim = summary["paper_claims"][0]
    assert lines[0].startswith("The paper's claim in its condition (patchy cone; cone-patchy;")
    assert lines[1].startswith(f"  {claim['baseline']} (") and lines[-1] == f"stripebench: results in {copy}"
    assert f"the 30 % improvement: {claims_of(claim)['improvement']}" in lines[1]
