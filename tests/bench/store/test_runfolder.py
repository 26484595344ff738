"""The run folder: one configuration per folder, a lock, validated readers,
damaged files recomputed, runs never outside the runs root."""

import importlib
import json
import subprocess
import sys
import time

import numpy as np
import pytest

from bench.store import runfolder
from bench.config import parse
from bench.run.experiment import run
from bench.store.runfolder import RunFolder, RunFolderError, default_run_dir, load_run, read_npz, safe_dir_name


def test_a_name_never_places_a_run_outside_the_runs_root(tiny_dict, tmp_path, monkeypatch):
    monkeypatch.setenv("STRIPEBENCH_RUNS", str(tmp_path / "runs"))
    for name in ("../../x", "/etc/passwd", "..", "a/../../b", ". .", "\x00"):
        out = default_run_dir(parse({**tiny_dict, "name": name}))
        assert out.resolve().is_relative_to((tmp_path / "runs").resolve()), (name, out)
        assert out.parent == tmp_path / "runs"
    assert safe_dir_name("../../x") == "x"


def test_a_folder_of_another_configuration_is_refused_then_cleared_with_force(tmp_path):
    folder = tmp_path / "run"
    with RunFolder(folder) as rf:
        rf.open({"name": "a", "seed": 0}, "code1")
    (folder / "figures").mkdir()
    (folder / "figures" / "shape_old.png").write_bytes(b"old")
    with pytest.raises(RunFolderError, match="holds a run of another configuration") as exc:
        RunFolder(folder).open({"name": "b", "seed": 1}, "code1")
    assert "--force" in str(exc.value) and "\n" not in str(exc.value)
    with RunFolder(folder) as rf:  # the same configuration: resumed, nothing removed
        rf.open({"name": "a", "seed": 0}, "code1")
    assert (folder / "figures" / "shape_old.png").exists()
    with RunFolder(folder) as rf:
        rf.open({"name": "b", "seed": 1}, "code1", force=True)
    assert not (folder / "figures").exists()
    assert json.loads((folder / "run.json").read_text())["name"] == "b"


def test_a_non_empty_folder_that_is_not_a_run_is_refused(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(RunFolderError, match="is not empty and is not a stripebench run folder"):
        RunFolder(tmp_path).open({"name": "a"}, "c")
    assert (tmp_path / "notes.txt").exists()


def test_changed_code_clears_the_results_but_keeps_the_checkpoints(tmp_path):
    notes = []
    with RunFolder(tmp_path / "r") as rf:
        rf.open({"name": "a"}, "code1")
    (tmp_path / "r" / "scans").mkdir()
    (tmp_path / "r" / "scans" / "x.npz").write_bytes(b"x")
    (tmp_path / "r" / "report.html").write_text("old")
    with RunFolder(tmp_path / "r") as rf:
        rf.open({"name": "a"}, "code2", say=notes.append)
    assert len(notes) == 1 and "code changed" in notes[0]
    assert not (tmp_path / "r" / "report.html").exists() and (tmp_path / "r" / "scans" / "x.npz").exists()


def test_out_that_is_a_file_is_refused(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(RunFolderError, match="is a file, not a folder"):
        RunFolder(f).open({}, "c")


_HOLD = """
import sys, time
from bench.store.runfolder import RunFolder
rf = RunFolder(sys.argv[1])
rf.lock()
print("locked", flush=True)
time.sleep(60)
"""


def test_a_second_process_on_the_same_folder_fails_at_once(tmp_path):
    folder = tmp_path / "run"
    folder.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", _HOLD, str(folder)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        t0 = time.monotonic()
        with pytest.raises(RunFolderError, match="is in use by another stripebench process"):
            RunFolder(folder).open({"name": "a"}, "c")
        assert time.monotonic() - t0 < 5
    finally:
        holder.kill()
        holder.wait()
        holder.stdout.close()
    with RunFolder(folder) as rf:  # the lock dies with its process
        rf.open({"name": "a"}, "c")


def test_read_npz_reports_damage_instead_of_raising(tmp_path):
    p = tmp_path / "a.npz"
    runfolder.save_npz(p, x=np.arange(1000.0))
    good, why = read_npz(p)
    assert why is None and good["x"].shape == (1000,)
    data = bytearray(p.read_bytes())
    data[len(data) // 2] ^= 0xFF  # a bit flip inside the compressed stream
    p.write_bytes(bytes(data))
    arrays, why = read_npz(p)
    assert arrays is None and why
    p.write_bytes(b"PK\x03\x04 not a zip")
    assert read_npz(p)[0] is None


@pytest.mark.slow
def test_a_corrupt_checkpoint_is_recomputed_in_one_rerun(gate_dict, tmp_path, capsys):
    cfg = parse(gate_dict)
    out = run(cfg, tmp_path / "r", progress=False, quiet=False)
    before = (out / "metrics.csv").read_bytes()
    ck = next((out / "scans").glob("*.npz"))
    data = bytearray(ck.read_bytes())
    for i in range(200, len(data) - 200, 97):
        data[i] ^= 0x55
    ck.write_bytes(bytes(data))
    (out / "figdata.npz").write_bytes(b"garbage")
    capsys.readouterr()
    run(cfg, out, progress=False, quiet=False)
    err = [line for line in capsys.readouterr().err.splitlines() if "checkpoint" in line]
    assert len(err) == 1 and "unreadable" in err[0] and "recomputing" in err[0]
    assert (out / "metrics.csv").read_bytes() == before
    assert read_npz(out / "figdata.npz")[0] is not None


@pytest.mark.slow
def test_damaged_figure_data_is_left_out_of_the_report_with_one_line(gate_run, tmp_path):
    import shutil

    out = tmp_path / "copy"
    shutil.copytree(gate_run[0], out)
    (out / "figdata.npz").write_bytes(b"\x00" * 10)
    notes = []
    data = load_run(out, say=notes.append)
    assert data["figdata"] is None and len(notes) == 1 and "figdata.npz" in notes[0]
    runfolder.save_npz(out / "figdata.npz", experiment=np.array("x"), mirror_angle_deg=np.array(0.0),
                       image=np.zeros((4, 5)), truth_columns=np.zeros(3), trackers=np.array(["a"]))
    notes.clear()
    assert load_run(out, say=notes.append)["figdata"] is None and "truth_columns" in notes[0]


@pytest.mark.slow
def test_corrupt_summary_or_metrics_are_one_line_errors(gate_run, tmp_path):
    import shutil

    out = tmp_path / "copy"
    shutil.copytree(gate_run[0], out)
    (out / "metrics.parquet").write_bytes(b"PAR1 nonsense")
    with pytest.raises(RunFolderError, match="cannot read .*metrics.parquet"):
        runfolder.load_metrics(out)
    (out / "summary.json").write_text("[1, 2")
    with pytest.raises(RunFolderError, match="is not valid JSON"):
        runfolder.load_summary(out)
    (out / "summary.json").write_text('{"config": null}')
    with pytest.raises(RunFolderError, match="`config` missing"):
        runfolder.load_summary(out)


_PLUGIN = '''
import numpy as np
from trackers import Track, Tracker

CALLS = []

class Plug(Tracker):
    name = "sbplug"
    def _track(self, image, background):
        CALLS.append(1)
        c = np.argmax(image, axis=1).astype(float) + OFFSET
        return Track(c, np.ones(image.shape[0]))

OFFSET = {offset}
'''


@pytest.mark.slow
def test_an_edited_plugin_tracker_invalidates_its_checkpoint(gate_dict, tmp_path, monkeypatch, register_tracker):
    mod_path = tmp_path / "sb_edit_plugin.py"
    mod_path.write_text(_PLUGIN.format(offset=0.0))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "sb_edit_plugin", raising=False)
    mod = importlib.import_module("sb_edit_plugin")
    register_tracker("sbplug", mod.Plug)
    cfg = parse({**gate_dict, "trackers": ["threshold", "sbplug"], "baselines": ["threshold"], "dp": ["sbplug"]})
    out = run(cfg, tmp_path / "r", progress=False, quiet=True)
    first = (out / "metrics.csv").read_text()
    # edit the plugin's source: the same configuration, other code
    mod_path.write_text(_PLUGIN.format(offset=0.25) + "\n# edited\n")
    mod = importlib.reload(mod)
    register_tracker("sbplug", mod.Plug, replace=True)
    mod.CALLS.clear()
    run(cfg, out, progress=False, quiet=True)
    assert len(mod.CALLS) > 0, "the old checkpoint was resumed"
    assert (out / "metrics.csv").read_text() != first
    mod.CALLS.clear()
    run(cfg, out, progress=False, quiet=True)  # unchanged code: resumed, the plugin is not called on frames
    assert len(mod.CALLS) == 0  # resumed: nothing to track, not even the warm-up on a blank frame


def test_force_resumes_a_folder_of_the_same_configuration(tmp_path):
    with RunFolder(tmp_path / "r") as rf:
        rf.open({"name": "a"}, "c")
    (tmp_path / "r" / "scans").mkdir()
    (tmp_path / "r" / "scans" / "x.npz").write_bytes(b"x")
    with RunFolder(tmp_path / "r") as rf:
        rf.open({"name": "a"}, "c", force=True)
    assert (tmp_path / "r" / "scans" / "x.npz").exists()


def test_a_run_folder_from_before_run_json_is_adopted_by_its_configuration(tmp_path):
    folder = tmp_path / "old"
    (folder / "scans").mkdir(parents=True)
    (folder / "config.json").write_text(json.dumps({"name": "a", "seed": 0}))
    (folder / "scans" / "x.npz").write_bytes(b"x")
    with pytest.raises(RunFolderError, match="another configuration|not a stripebench run folder"):
        RunFolder(folder).open({"name": "a", "seed": 1}, "c")
    with RunFolder(folder) as rf:
        rf.open({"name": "a", "seed": 0}, "c")
    assert (folder / "scans" / "x.npz").exists() and (folder / "run.json").exists()


# -- one guard for every kind of run ----------------------------------------------------------------------------


@pytest.mark.parametrize("first, second", [("run", "real"), ("run", "sweep"), ("real", "sweep"), ("sweep", "track"),
                                           ("track", "real")])
def test_a_folder_of_another_kind_is_refused_then_cleared_with_force(first, second, tmp_path):
    folder = tmp_path / "f"
    with RunFolder(folder, kind=first) as rf:
        rf.open({"name": "a"}, "c")
    (folder / "summary.json").write_text("{}")
    with pytest.raises(RunFolderError, match=f"holds a {runfolder.KINDS[first]} .*not a {runfolder.KINDS[second]}"
                                             ".*pass --force to clear it") as exc:
        RunFolder(folder, kind=second).open({"name": "a"}, "c")  # the same configuration, another kind
    assert "\n" not in str(exc.value) and (folder / "summary.json").read_text() == "{}"
    with RunFolder(folder, kind=second) as rf:
        rf.open({"name": "a"}, "c", force=True)
    assert not (folder / "summary.json").exists()
    assert json.loads((folder / "run.json").read_text())["kind"] == second


def test_a_format_1_run_record_is_a_synthetic_run(tmp_path):
    folder = tmp_path / "f"
    folder.mkdir()
    (folder / "run.json").write_text(json.dumps({"format": 1, "name": "a", "config_hash": runfolder.config_hash({"name": "a"}),
                                                 "code": "c"}))
    (folder / "report.html").write_text("kept")
    with RunFolder(folder) as rf:
        rf.open({"name": "a"}, "c")
    assert (folder / "report.html").exists() and json.loads((folder / "run.json").read_text())["format"] == 2
    with pytest.raises(RunFolderError, match="holds a run .*not a real run"):
        RunFolder(folder, kind="real").open({"name": "a"}, "c")


def test_a_run_record_of_a_newer_format_is_refused(tmp_path):
    folder = tmp_path / "f"
    folder.mkdir()
    (folder / "run.json").write_text(json.dumps({"format": 99, "config_hash": "x", "kind": "run"}))
    with pytest.raises(RunFolderError, match="written by a newer stripebench .*format 99"):
        RunFolder(folder).open({"name": "a"}, "c")
    with RunFolder(folder) as rf:
        rf.open({"name": "a"}, "c", force=True)


@pytest.mark.parametrize("damage", ["not json", "a list", "a directory", "not utf-8"])
def test_an_unreadable_run_record_is_one_line_and_keeps_the_good_checkpoints(damage, tmp_path):
    from bench.store.checkpoint import ScanResult, write_checkpoint

    folder = tmp_path / "f"
    with RunFolder(folder) as rf:
        rf.open({"name": "a"}, "c")
    write_checkpoint(folder / "scans" / "good.npz", ScanResult.empty("good", [0.0, 1.0], 4, ["t"]))
    (folder / "scans" / "bad.npz").write_bytes(b"PK\x03\x04 damaged")
    (folder / "metrics.csv").write_text("old results")
    rec = folder / "run.json"
    rec.unlink()
    if damage == "a directory":
        rec.mkdir()
    else:
        rec.write_bytes({"not json": b"{", "a list": b"[]", "not utf-8": b"\xff\xfe"}[damage])
    notes = []
    with RunFolder(folder) as rf:
        rf.open({"name": "a"}, "c", say=notes.append)
    assert len(notes) == 1 and "run.json is" in notes[0] and "recovered" in notes[0] and "kept 1" in notes[0]
    assert sorted(p.name for p in (folder / "scans").iterdir()) == ["good.npz"]
    assert not (folder / "metrics.csv").exists() and json.loads(rec.read_text())["kind"] == "run"


def test_an_unreadable_run_record_of_another_configuration_is_refused(tmp_path):
    folder = tmp_path / "f"
    with RunFolder(folder) as rf:
        rf.open({"name": "b"}, "c")
    (folder / "run.json").write_text("{")
    with pytest.raises(RunFolderError, match="another configuration .*run.json is unreadable"):
        RunFolder(folder).open({"name": "a"}, "c")


def test_a_directory_where_the_lock_should_be_is_removed_with_one_line(tmp_path):
    folder = tmp_path / "f"
    (folder / ".lock" / "x").mkdir(parents=True)
    notes = []
    with RunFolder(folder) as rf:
        rf.open({"name": "a"}, "c", say=notes.append)
    assert len(notes) == 1 and ".lock was a directory" in notes[0] and (folder / ".lock").is_file()


def test_a_file_where_the_checkpoints_folder_should_be_is_removed(tmp_path):
    folder = tmp_path / "f"
    with RunFolder(folder) as rf:
        rf.open({"name": "a"}, "c")
    (folder / "scans").write_text("x")
    notes = []
    with RunFolder(folder) as rf:
        rf.open({"name": "a"}, "c", say=notes.append)
    assert not (folder / "scans").exists() and len(notes) == 1 and "scans was a file" in notes[0]


def test_changed_code_keeps_a_sweeps_units_and_not_a_track_folders_outputs(tmp_path):
    with RunFolder(tmp_path / "s", kind="sweep") as rf:
        rf.open({"name": "a"}, "c1")
    (tmp_path / "s" / "units").mkdir()
    (tmp_path / "s" / "units" / "u.json").write_text("{}")
    (tmp_path / "s" / "sweep.csv").write_text("old")
    with RunFolder(tmp_path / "s", kind="sweep") as rf:
        rf.open({"name": "a"}, "c2")
    assert (tmp_path / "s" / "units" / "u.json").exists() and not (tmp_path / "s" / "sweep.csv").exists()
    with RunFolder(tmp_path / "t", kind="track") as rf:
        rf.open({"trackers": ["t"]}, "c1")
    (tmp_path / "t" / "a.csv").write_text("row\n")
    with RunFolder(tmp_path / "t", kind="track") as rf:
        rf.open({"trackers": ["t"]}, "c2")
    assert (tmp_path / "t" / "a.csv").exists()  # a track folder gathers outputs of several commands


def test_an_unknown_kind_is_a_programming_error():
    with pytest.raises(ValueError, match="`kind` must be one of run, real, sweep, track, score"):
        RunFolder("x", kind="nope")
