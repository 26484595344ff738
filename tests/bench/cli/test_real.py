"""``stripebench track`` and ``stripebench real`` (bench/cli/real.py)."""

import shutil

import pytest

from bench.cli import main
from bench.store.realset import SHIPPED
from cli_helpers import cli, one_line, one_line_err


@pytest.fixture
def small_set(tmp_path):
    """A copy of the shipped set's first two photographs (manifest rewritten)."""
    d = tmp_path / "set"
    d.mkdir()
    lines = (SHIPPED / "manifest.csv").read_text(encoding="utf-8").splitlines()
    header, rows = lines[0], lines[1:3]
    for row in rows:
        name = row.split(",")[0]
        for f in SHIPPED.glob(f"{name}*"):
            if f.name in (f"{name}.png", f"{name}_off.png", f"{name}_ref.csv"):
                shutil.copy(f, d / f.name)
    (d / "manifest.csv").write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    return d


@pytest.mark.parametrize("tol, message", [("inf", "got 'inf'"), ("nan", "got 'nan'"), ("0", "got '0'"),
                                          ("-3", "got '-3'")])
def test_real_tol_must_be_finite_positive_before_tracking(small_set, tmp_path, tol, message):
    proc = cli("real", small_set, "--tol", tol, "--out", tmp_path / "o")
    one_line(proc, "argument --tol: must be a finite number > 0", message)
    assert not (tmp_path / "o").exists()


def test_a_manifest_rotate_that_is_not_an_angle_is_one_line(small_set, tmp_path):
    m = small_set / "manifest.csv"
    lines = m.read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    k = header.index("rotate")
    fields = lines[1].split(",")
    fields[k] = "²"
    m.write_text("\n".join([lines[0], ",".join(fields), *lines[2:]]) + "\n", encoding="utf-8")
    one_line(cli("real", small_set, "--out", tmp_path / "o"), "rotate must be one of 0, 90, 180, 270, got '²'",
             "and 0 more" if False else "rotate")
    assert not (tmp_path / "o").exists()


def test_an_undecodable_reference_csv_is_one_line(small_set, tmp_path, capsys):
    ref = next(small_set.glob("*_ref.csv"))
    ref.write_bytes(b"row,col\n0,\xff\xfe\n")
    one_line(cli("real", small_set, "--out", tmp_path / "o"), ref.name, "not UTF-8 text")
    assert main(["real", str(small_set), "--check"]) == 2  # --check: one line per problem
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and ref.name in err[0] and err[0].startswith("stripebench real:")


def test_a_folder_that_is_not_a_real_set_is_one_line(tmp_path):
    one_line(cli("real", tmp_path, "--out", tmp_path / "o"), "is not a valid real set", "no manifest.csv")


def test_track_out_a_file_and_a_bad_background_are_one_line(tmp_path, capsys):
    img = next(SHIPPED.glob("*.png"))
    f = tmp_path / "afile"
    f.write_text("x")
    assert main(["track", str(img), "--out", str(f)]) == 2
    one_line_err(capsys, "--out must be a folder")
    assert main(["track", str(img), "--out", str(tmp_path / "o"), "--background", str(f)]) == 2
    one_line_err(capsys, "--background:")


def test_by_rig_prints_each_rig_with_intervals_and_all_rigs_over_rigs(tmp_path):
    """``real --by-rig`` on a set of three photographs from two rigs (the manifest's ``rig``): one line per rig and
    tracker, the rig of two photographs with an interval, the rig of one without, and all rigs; the same figures as
    ``summary.json`` holds, computed from the photographs' row outcomes."""
    import json

    import numpy as np

    d = tmp_path / "set"
    d.mkdir()
    lines = (SHIPPED / "manifest.csv").read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    k = header.index("rig")
    chosen = [row for row in lines[1:] if row.split(",")[0] in ("al_room0", "al_room1", "bb_board")]
    for row in chosen:
        name = row.split(",")[0]
        for suffix in (".png", "_ref.csv"):
            shutil.copy(SHIPPED / f"{name}{suffix}", d / f"{name}{suffix}")
    (d / "manifest.csv").write_text("\n".join([lines[0], *chosen]) + "\n", encoding="utf-8")
    rigs = {row.split(",")[0]: row.split(",")[k] for row in chosen}
    assert sorted(set(rigs.values())) == ["albrecht", "b33boy"]
    proc = cli("real", d, "--out", tmp_path / "o", "--quiet", "--trackers", "threshold,dp8", "--by-rig",
               "--n-boot", "200", timeout=300)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout.splitlines()
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    for lab in ("threshold", "dp8"):
        start = out.index(lab)
        block = out[start + 2:start + 5]
        assert [b.split()[0] for b in block] == ["albrecht", "b33boy", "all"]
        r = summary["trackers"][lab]["rigs"]
        alb, bb = r["rigs"]["albrecht"], r["rigs"]["b33boy"]
        assert alb["n_photos"] == 2 and bb["n_photos"] == 1 and r["all"]["n_rigs"] == 2
        assert np.isfinite(alb["f1_lo"]) and np.isnan(bb["f1_lo"])
        assert f"{alb['f1']:.3f} [{alb['f1_lo']:.3f}, {alb['f1_hi']:.3f}]" in block[0]
        assert f"{bb['f1']:.3f} [–]" in block[1]
        # the rig's figure is its photographs' rows pooled (metrics.csv holds each photograph's counts)
        import pandas as pd

        m = pd.read_csv(tmp_path / "o" / "metrics.csv")
        sub = m[(m["tracker"] == lab) & m["experiment"].isin(["al_room0", "al_room1"])]
        hit, wrong, missed, false = (int(sub[f"n_{o}"].sum()) for o in ("hit", "wrong", "missed", "false"))
        assert alb["f1"] == pytest.approx(2 * hit / (2 * hit + 2 * wrong + missed + false))
