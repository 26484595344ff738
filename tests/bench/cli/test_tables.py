"""``stripebench tables RUN`` (bench/cli/tables.py): the README's tables, computed from a run's files."""

import hashlib
import json
import shutil

import pytest

from bench.cli import main
from cli_helpers import one_line_err, status


def _copy(run, dest):
    """A committed copy of a run: its summary and metrics only (as results/paper holds them)."""
    dest.mkdir()
    for name in ("summary.json", "metrics.csv"):
        shutil.copy(run / name, dest / name)
    return dest


def test_the_tables_are_computed_from_the_run_files(tiny_run, tmp_path, capsys):
    out, _ = tiny_run
    copy = _copy(out, tmp_path / "paper")
    assert main(["tables", str(copy), "--markdown"]) == 0
    before = capsys.readouterr().out
    summary = json.loads((copy / "summary.json").read_text())
    first = next(r for r in summary["robust"] if r["group"] == "cone-patchy" and r["tracker"] == "dp4")
    cell = f"{100 * first['within']:.0f} [{100 * first['within_low']:.0f}, {100 * first['within_high']:.0f}]"
    assert f"| patchy cone | " in before and cell in before.split("| patchy cone |")[1].splitlines()[0]
    digest = hashlib.sha256((copy / "metrics.csv").read_bytes()).hexdigest()
    assert f"`metrics.csv` sha256 `{digest}`" in before and summary["metrics_sha256"] == digest
    assert f"at git `{summary['git_revision']}`" in before and f"rendered by `{summary['renderer']}`" in before
    assert f"machine: {summary['machine']['cpu']} ({summary['machine']['cores']} cores" in before
    # a number changed in the copy changes the table
    first.update(within=0.123, within_low=0.051, within_high=0.201)
    det = next(r for r in summary["detection"] if r["group"] == "condition:patchy cone" and r["tracker"] == "dp4")
    det.update(f1=0.321, false_report_rate=0.654)
    (copy / "summary.json").write_text(json.dumps(summary))
    assert main(["tables", str(copy), "--markdown"]) == 0
    after = capsys.readouterr().out
    assert after != before and "12 [5, 20]" in after and "0.32 / 65 %" in after and "12 [5, 20]" not in before


def test_plain_text_tables_and_chosen_columns(tiny_run, tmp_path, capsys):
    out, _ = tiny_run
    assert main(["tables", str(out), "--trackers", "dp8,threshold", "--ratios", "dp8"]) == 0
    text = capsys.readouterr().out
    head = next(ln for ln in text.splitlines() if ln.startswith("condition"))
    assert head.split() == ["condition", "dp8", "threshold", "ratio", "dp8"] and "|" not in head


@pytest.mark.parametrize("argv_tail, message", [
    (["--trackers", "nope"], "--trackers: 'nope' is no tracker of this run"),
    (["--ratios", "threshold"], "--ratios: 'threshold' is not a DP label of this run"),
    (["--trackers", ","], "must be comma-separated tracker labels"),
])
def test_bad_options_are_one_line(tiny_run, argv_tail, message, capsys):
    out, _ = tiny_run
    assert status(["tables", str(out), *argv_tail]) == 2
    one_line_err(capsys, message)


def test_a_metrics_file_of_another_run_is_refused(tiny_run, tmp_path, capsys):
    out, _ = tiny_run
    copy = _copy(out, tmp_path / "paper")
    (copy / "metrics.csv").write_text((copy / "metrics.csv").read_text() + "\n")
    assert main(["tables", str(copy)]) == 2
    one_line_err(capsys, "is not the metrics file of this run's summary")
    (copy / "metrics.csv").unlink()
    assert main(["tables", str(copy)]) == 2
    one_line_err(capsys, "RUN must hold the run's metrics.csv", "missing")
    assert main(["tables", str(tmp_path / "nothing")]) == 2
    one_line_err(capsys, "RUN must be a finished run folder")


def test_the_committed_copy_gives_the_same_tables(tiny_run, tmp_path, capsys):
    out, _ = tiny_run
    dest = tmp_path / "results" / "paper"
    assert main(["tables", str(out), "--markdown", "--save", str(dest)]) == 0
    whole = capsys.readouterr().out
    assert sorted(p.name for p in dest.iterdir()) == ["metrics.csv", "summary.json"]
    assert (dest / "metrics.csv").read_bytes() == (out / "metrics.csv").read_bytes()
    cut = json.loads((dest / "summary.json").read_text())
    full = json.loads((out / "summary.json").read_text())
    assert "verdicts" in full and "verdicts" not in cut and cut["metrics_sha256"] == full["metrics_sha256"]
    assert all(i["statistic"] == "rmse" for i in cut["improvement"]) and len(cut["improvement"]) < len(
        full["improvement"])
    assert main(["tables", str(dest), "--markdown"]) == 0
    assert capsys.readouterr().out == whole
    assert main(["tables", str(out), "--save", str(out)]) == 2
    one_line_err(capsys, "--save must name another folder than RUN")


def test_the_committed_paper_copy_is_the_paper_profiles_and_whole(capsys):
    """results/paper (the README's tables) is a run of today's `paper` profile, its two files from one run."""
    from pathlib import Path

    from bench.config import profile

    paper = Path(__file__).resolve().parents[3] / "results" / "paper"
    summary = json.loads((paper / "summary.json").read_text())
    assert summary["config"] == profile("paper").to_dict(), "the paper profile changed: regenerate results/paper"
    assert main(["tables", str(paper), "--markdown"]) == 0
    out = capsys.readouterr().out
    assert f"`metrics.csv` sha256 `{summary['metrics_sha256']}`" in out and "machine: not recorded" not in out
