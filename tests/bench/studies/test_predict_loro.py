"""``stripebench predictloro`` on a small labelled set of three rigs: measured, predicted, judged leave one rig out,
and the calibration it writes read back by ``predict``."""

import json

import imageio.v3 as iio
import numpy as np

from bench.cli import main


def _real_set(root):
    """Three rigs of two grey photographs each: a stripe at column 40 (stripe rows 0-79, none below) and, on rig
    ``c``, a brighter bar beside it in some rows."""
    root.mkdir()
    rng = np.random.default_rng(7)
    x = np.arange(96.0)
    rows = ["name,has_background,laser_colour,rig"]
    for rig in ("a", "b", "c"):
        for k in range(2):
            name = f"{rig}{k}"
            img = 25.0 + rng.normal(0, 2.0, (120, 96))
            img[:80] += (90.0 + 20 * k) * np.exp(-0.5 * ((x - 40.0) / 1.3) ** 2)
            if rig == "c":
                img[20:60, 70:73] += 160.0
            iio.imwrite(root / f"{name}.png", np.clip(np.rint(img), 0, 255).astype(np.uint8))
            ref = ["row,col,state"] + [f"{r},40,stripe" if r < 80 else f"{r},,none" for r in range(120)]
            (root / f"{name}_ref.csv").write_text("\n".join(ref) + "\n")
            rows.append(f"{name},0,red,{rig}")
    (root / "manifest.csv").write_text("\n".join(rows) + "\n")
    return root


def test_predictloro_judges_each_rig_held_out_and_writes_a_calibration_predict_reads(tmp_path, capsys):
    ds = _real_set(tmp_path / "set")
    out, cal = tmp_path / "loro", tmp_path / "cal.json"
    assert main(["predictloro", str(ds), "--out", str(out), "--trackers", "threshold,dp8,steger", "--n-boot", "50",
                 "--calibration", str(cal), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "leave one rig out: predict / null" in printed and "all rigs" in printed
    doc = json.loads((out / "predict_loro.json").read_text())
    assert list(doc["rigs"]) == ["a", "b", "c"] and doc["trackers"] == ["threshold", "dp8", "steger"]
    for rig, e in doc["rigs"].items():
        assert e["n_photos"] == 2 and e["n_predicted"] == 2
        assert e["f1"]["method"]["n_intervals"] == 3 and 0 <= e["f1"]["method"]["covered"] <= 3
        assert np.isfinite(e["f1"]["null"]["error"]) and e["regret"]["null"] >= 0
    p = doc["pooled"]
    assert p["f1"]["method"]["n_intervals"] == 9 and 0.0 <= p["f1"]["method"]["coverage"] <= 1.0
    assert doc["provenance"]["n_photos"] == 6 and len(doc["provenance"]["manifest_sha256"]) == 64
    from bench.store.predictfiles import read_calibration

    c = read_calibration(cal)
    assert c["rigs"] == ["a", "b", "c"] and set(c["f1"]["null"]) == {"threshold", "dp8", "steger"}
    assert c["f1"]["source"] in ("method", "null") and c["loro"]["regret"] == p["regret"]
    photos = tmp_path / "mine"
    photos.mkdir()
    iio.imwrite(photos / "x.png", iio.imread(ds / "c0.png"))
    assert main(["predict", str(photos), "--out", str(tmp_path / "p"), "--trackers", "threshold,dp8,steger",
                 "--n-boot", "50", "--calibration", str(cal), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("use ") and "on the shipped set (3 rigs)" in lines[1]
    pred = json.loads((tmp_path / "p" / "predict.json").read_text())
    assert pred["calibration"]["manifest_sha256"] == doc["provenance"]["manifest_sha256"]
    assert pred["pick"]["loro_regret"] == p["regret"]
