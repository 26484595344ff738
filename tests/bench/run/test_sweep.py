"""Sweeps: grid expansion and validation, units, and real runs on tiny renders
(sequential, a LocalCluster of processes, an external scheduler with two workers)."""

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import bench.run.sweep as sw
from bench.config import ConfigError, parse
from bench.run.experiment import run
from bench.run.sweep import Sweep, load, parse_sweep, plan, run_sweep
from bench.report.sweep import build_report

REPO = Path(__file__).resolve().parents[3]

BASE = {
    "name": "tinysweep",
    "seed": 2,
    "trackers": ["threshold", "dp8"],
    "baselines": ["threshold"],
    "dp": ["dp8"],
    "n_samples": 15,
    "n_boot": 20,
    "render": {"width": 64, "height": 60, "spp": 2, "ambient_spp": 1},
    "experiments": [{"scene": "cone", "material": "patchy", "n_angles": 3}],
}
GRID = {"ambient_lux": [0, 400, 2000], "laser_power_mw": [1.0, 3.0], "repeats": 2}


def _toml(tmp_path, sweep_lines: str, experiments: str = None) -> Path:
    exps = experiments or '[[experiments]]\nscene = "cone"\nmaterial = "patchy"\nn_angles = 2\n'
    text = ('name = "tinysweep"\nseed = 2\ntrackers = ["threshold", "dp8"]\nbaselines = ["threshold"]\n'
            'dp = ["dp8"]\nn_samples = 15\nn_boot = 20\n[render]\nwidth = 64\nheight = 60\nspp = 2\n'
            f'ambient_spp = 1\n{exps}[sweep]\n{sweep_lines}\n')
    p = tmp_path / "sweep.toml"
    p.write_text(text)
    return p


# -- grid and validation -----------------------------------------------------------------------------------------

def test_grid_is_the_product_in_written_order(tmp_path):
    cfg, s = load(_toml(tmp_path, "ambient_lux = [0, 100, 400, 1000, 2000]\nlaser_power_mw = [1.0, 3.0, 10.0]\n"
                                  "repeats = 3"))
    assert s.keys == ("ambient_lux", "laser_power_mw") and s.repeats == 3
    pts = s.points()
    assert len(pts) == 15
    assert pts[0] == {"ambient_lux": 0.0, "laser_power_mw": 1.0}
    assert pts[1] == {"ambient_lux": 0.0, "laser_power_mw": 3.0}
    assert pts[-1] == {"ambient_lux": 2000.0, "laser_power_mw": 10.0}
    assert len({tuple(p.values()) for p in pts}) == 15
    assert cfg.name == "tinysweep"


def test_repeats_default_to_one(tmp_path):
    _, s = load(_toml(tmp_path, "exposure_ms = [2.0, 5.0]"))
    assert s.repeats == 1 and s.points() == [{"exposure_ms": 2.0}, {"exposure_ms": 5.0}]


@pytest.mark.parametrize("lines, message", [
    ("albedo = [0.1, 0.5]", "unknown key `sweep.albedo`"),
    ("ambient_lux = []", "`sweep.ambient_lux` must be a non-empty list of values, got \\[\\]"),
    ("ambient_lux = 400", "`sweep.ambient_lux` must be a non-empty list of values, got 400"),
    ("ambient_lux = [0, -5]", "`sweep.ambient_lux` = -5.0 .*ambient_lux"),
    ("laser_power_mw = [1.0, true]", "`sweep.laser_power_mw` must hold numbers or names, got True"),
    ("material = [\"matte\", \"velvet\"]", "`sweep.material` = 'velvet'"),
    ("ambient_lux = [0, 0]", "`sweep.ambient_lux` repeats a value"),
    ("ambient_lux = [0]\nrepeats = 0", "`sweep.repeats` must be an integer 1 .. 1000, got 0"),
    ("ambient_lux = [0]\nrepeats = 1000000000", "`sweep.repeats` must be an integer 1 .. 1000, got 1000000000"),
    ("ambient_lux = [0, 1e7]", "`sweep.ambient_lux` = 10000000.0 .*must be at most 1e\\+06"),
    ("laser_power_mw = [3, 1e6]", "`sweep.laser_power_mw` = 1000000.0 .*must be at most 100000"),
    ("exposure_ms = [5, 1e5]", "`sweep.exposure_ms` = 100000.0 .*must be at most 10000"),
    ("f_number = [2.8, 0.01]", "`sweep.f_number` = 0.01 .*must be at least 0.5"),
    ("ambient_lux = [" + ", ".join(str(i) for i in range(3000)) + "]\nlaser_power_mw = ["
     + ", ".join(str(i) for i in range(3000)) + "]", "`sweep` has 9000000 grid points .*; at most 100000"),
    ("repeats = 2", "`sweep` must sweep at least one key"),
])
def test_bad_sweeps_raise_one_line(tmp_path, lines, message):
    with pytest.raises(ConfigError, match=message) as err:
        load(_toml(tmp_path, lines))
    assert "\n" not in str(err.value)


def test_parse_sweep_rejects_a_non_table():
    with pytest.raises(ConfigError, match="`sweep` must be a table, got"):
        parse_sweep([1, 2], parse(BASE))


def test_run_on_a_sweep_configuration_says_to_use_sweep(tmp_path):
    with pytest.raises(ConfigError, match="stripebench sweep"):
        parse({**BASE, "sweep": {"ambient_lux": [0]}})


def test_plan_splits_render_batches_and_chunks():
    cfg = parse(BASE)
    s = Sweep((("material", ("matte", "absorbing")), ("ambient_lux", (0.0, 400.0, 1000.0))), repeats=2)
    units = plan(cfg, s)
    assert len(units) == 2  # one render batch per material, every lux point reuses it
    assert [u["render_overrides"] for u in units] == [{"material": "matte"}, {"material": "absorbing"}]
    assert all(len(u["points"]) == 3 for u in units)
    chunked = plan(cfg, s, chunk=2)
    assert [len(u["points"]) for u in chunked] == [2, 1, 2, 1]
    assert sorted(p["index"] for u in chunked for p in u["points"]) == list(range(6))
    scale_only = plan(cfg, Sweep((("ambient_lux", (0.0, 400.0)), ("laser_power_mw", (1.0, 3.0))), 1))
    assert len(scale_only) == 1 and scale_only[0]["render_overrides"] == {}
    with pytest.raises(ValueError, match="`chunk` must be an integer >= 1, got 0"):
        plan(cfg, s, chunk=0)


# -- real sweeps -------------------------------------------------------------------------------------------------

def _cfg_sweep():
    cfg = parse(BASE)
    return cfg, parse_sweep(dict(GRID), cfg)


def _table(out):
    return pd.read_parquet(Path(out) / "sweep.parquet")


@pytest.fixture(scope="module")
def sequential(tmp_path_factory):
    cache = tmp_path_factory.mktemp("cold-cache")
    saved = os.environ.get("STRIPEBENCH_CACHE_DIR")
    os.environ["STRIPEBENCH_CACHE_DIR"] = str(cache)
    try:
        cfg, s = _cfg_sweep()
        out = run_sweep(cfg, s, tmp_path_factory.mktemp("seq"), scheduler="sync", progress=False, quiet=True)
        build_report(out)
    finally:
        os.environ["STRIPEBENCH_CACHE_DIR"] = saved
    return out, cache


@pytest.mark.slow
def test_sequential_sweep_writes_the_tidy_table_and_report(sequential):
    out, _ = sequential
    t = _table(out)
    assert len(t) == 1 * 6 * 2 * 2  # experiments x grid points x repeats x trackers
    assert {"experiment", "ambient_lux", "laser_power_mw", "repeat", "tracker", "hit_rate", "depth_mae_mm",
            "depth_rmse_mm", "within_5mm", "coverage", "outlier_rate"} <= set(t.columns)
    assert not t.duplicated(["experiment", "point", "repeat", "tracker"]).any()
    assert pd.read_csv(out / "sweep.csv").shape == t.shape
    assert t["hit_rate"].between(0, 1).all() and t["within_5mm"].between(0, 1).all()
    s = json.loads((out / "summary.json").read_text())
    assert s["sweep"] == {"ambient_lux": [0.0, 400.0, 2000.0], "laser_power_mw": [1.0, 3.0], "repeats": 2}
    assert s["engine"]["engine"] == "sync" and s["costs"][0]["frames"] == 3 and s["costs"][0]["evaluations"] == 36
    assert {c["key"] for c in s["curves"]} == {"ambient_lux", "laser_power_mw"}
    page = (out / "report.html").read_text()
    assert page.count("data:image/png;base64,") == 1 and "src=\"http" not in page
    # more laser power never lowers the stripe level: the threshold's hit rate at 0 lux does not drop
    th = t[(t.tracker == "threshold") & (t.ambient_lux == 0)].groupby("laser_power_mw")["hit_rate"].mean()
    assert th[3.0] >= th[1.0]


@pytest.mark.slow
def test_scale_only_grid_points_reuse_the_renders(sequential):
    _, cache = sequential
    # 3 angles x 6 grid points x 2 repeats evaluated, but only the 3 unit renders were made
    assert len(list(Path(cache).rglob("*.npz"))) == 3


@pytest.mark.slow
def test_repeats_vary_the_sensor_noise_not_the_render(sequential):
    t = _table(sequential[0])
    dp = t[t.tracker == "dp8"].set_index(["point", "repeat"])
    assert (dp.xs(0, level="repeat")["n_lit_object"] == dp.xs(1, level="repeat")["n_lit_object"]).all()
    assert not np.allclose(dp.xs(0, level="repeat")["depth_mae_mm"], dp.xs(1, level="repeat")["depth_mae_mm"])


@pytest.mark.slow
def test_repeat_zero_at_the_paper_point_matches_an_ordinary_run(sequential, tmp_path):
    t = _table(sequential[0])
    ref = run(parse(BASE), tmp_path / "run", progress=False, quiet=True)  # 400 lux, 3 mW defaults
    m = pd.read_parquet(ref / "metrics.parquet")
    m = m[m.region == "object"].set_index("tracker")
    row = t[(t.ambient_lux == 400) & (t.laser_power_mw == 3.0) & (t.repeat == 0)].set_index("tracker")
    for col in ("hit_rate", "depth_mae_mm", "depth_rmse_mm", "coverage", "outlier_rate"):
        assert np.allclose(row.loc[m.index, col], m[col], equal_nan=True), col
    # the ±5 mm fraction comes from the same sample points and restored surfaces as the run's samples.csv
    s = pd.read_csv(ref / "samples.csv")
    for tracker in m.index:
        within = float(np.mean(np.abs(s[f"error_mm_{tracker}"].dropna()) <= 5.0))
        assert row.loc[tracker, "within_5mm"] == pytest.approx(within)


@pytest.mark.slow
def test_local_cluster_gives_the_sequential_table(sequential, tmp_path):
    cfg, s = _cfg_sweep()
    out = run_sweep(cfg, s, tmp_path / "local", workers=2, chunk=3, progress=False, quiet=True,
                    timeout_s=300, connect_timeout_s=60)
    info = json.loads((out / "summary.json").read_text())["engine"]
    assert info["engine"] == "local" and info["scheduler"].startswith("tcp://127.0.0.1:")
    pd.testing.assert_frame_equal(_table(out), _table(sequential[0]))


def _wait_for(path: Path, proc, timeout_s: float) -> None:
    deadline = time.monotonic() + timeout_s
    while not path.exists():
        if proc.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError(f"{path} did not appear (process exited {proc.poll()})")
        time.sleep(0.2)


@pytest.mark.slow
def test_external_scheduler_and_two_workers_give_the_sequential_table(sequential, tmp_path):
    from dask.distributed import Client

    sched_file = tmp_path / "scheduler.json"
    from scenes import variant

    env = {**os.environ, "PYTHONPATH": str(REPO), variant.ENV_VARIANT: variant.choose()}  # no probing per worker
    procs = []
    try:
        procs.append(subprocess.Popen(
            [sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", str(sched_file)], cwd=REPO, env=env, stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL))
        _wait_for(sched_file, procs[0], 60)
        for _ in range(2):
            procs.append(subprocess.Popen(
                [sys.executable, "-m", "dask", "worker", "--scheduler-file", str(sched_file), "--host", "127.0.0.1",
                 "--nthreads", "1", "--no-dashboard", "--death-timeout", "60", "--local-directory",
                 str(tmp_path / "workers")], cwd=REPO, env=env, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL))
        address = json.loads(sched_file.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        with Client(address, timeout=30) as c:
            c.wait_for_workers(2, timeout=90)
        cfg, s = _cfg_sweep()
        out = run_sweep(cfg, s, tmp_path / "ext", scheduler=address, chunk=2, progress=False, quiet=True,
                        timeout_s=300, connect_timeout_s=30)
        info = json.loads((out / "summary.json").read_text())
        assert info["engine"] == {"engine": "external", "scheduler": address, "workers": 2}
        assert len(info["units"]) == 3
        pd.testing.assert_frame_equal(_table(out), _table(sequential[0]))
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait(timeout=10)


def test_unreachable_scheduler_is_one_line(tmp_path):
    import socket

    with socket.socket() as s:  # a free port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    cfg, sweep = _cfg_sweep()
    with pytest.raises(sw.SweepError, match=f"cannot reach the Dask scheduler at 'tcp://127.0.0.1:{port}'"):
        run_sweep(cfg, sweep, tmp_path / "x", scheduler=f"tcp://127.0.0.1:{port}", progress=False, quiet=True,
                  connect_timeout_s=2)


@pytest.mark.slow
def test_an_interrupted_sweep_resumes_without_redoing_finished_units(sequential, tmp_path, monkeypatch):
    cfg, s = _cfg_sweep()
    out = tmp_path / "resume"
    real_save, real_unit = sw._save_unit, sw.run_unit
    saves = []

    def save_then_interrupt(path, result):
        real_save(path, result)
        saves.append(path)
        if len(saves) == 1:
            raise KeyboardInterrupt

    monkeypatch.setattr(sw, "_save_unit", save_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(cfg, s, out, scheduler="sync", chunk=2, progress=False, quiet=True)
    assert len(list((out / "units").glob("*.json"))) == 1 and not (out / "sweep.parquet").exists()
    calls = []
    monkeypatch.setattr(sw, "run_unit", lambda spec: calls.append(spec) or real_unit(spec))
    run_sweep(cfg, s, out, scheduler="sync", chunk=2, progress=False, quiet=True)
    assert len(calls) == 2  # of 3 units, the finished one was skipped
    pd.testing.assert_frame_equal(_table(out), _table(sequential[0]))
    calls.clear()
    run_sweep(cfg, s, out, scheduler="sync", chunk=2, progress=False, quiet=True)
    assert calls == []  # everything done: nothing recomputed


def test_bad_engine_arguments(tmp_path):
    cfg, s = _cfg_sweep()
    with pytest.raises(ConfigError, match=r"`workers` must be an integer 0 \.\. \d+, got -1"):
        run_sweep(cfg, s, tmp_path, workers=-1)
    with pytest.raises(ConfigError, match=r"`workers` must be an integer 0 \.\. \d+, got 100000"):
        run_sweep(cfg, s, tmp_path, workers=100000)
    with pytest.raises(ConfigError, match="`scheduler` must be 'sync' or an address like tcp://HOST:PORT"):
        run_sweep(cfg, s, tmp_path, scheduler="x")
    for bad in ("tcp://", "tcp://127.0.0.1:notaport", "tcp://127.0.0.1:0", "http://127.0.0.1:8786"):
        with pytest.raises(ConfigError, match="`scheduler` must be 'sync' or an address"):
            run_sweep(cfg, s, tmp_path, scheduler=bad)
    with pytest.raises(ConfigError, match=r"`timeout_s` must be a finite number > 0, got nan"):
        run_sweep(cfg, s, tmp_path, timeout_s=float("nan"))
    assert not (tmp_path / "config.json").exists()  # refused before anything was written


@pytest.mark.parametrize("setting", [{"name": "dp4", "timeout_s": 5.0}, {"name": "dp4", "isolate": True}])
def test_timeout_s_and_isolate_are_refused_where_dask_cannot_honour_them(tmp_path, setting):
    """Issue 37 item 3: a Dask worker runs a unit in a thread of a daemonic process, where neither SIGALRM
    nor a worker process can be set up; the sync scheduler honours both."""
    import copy

    base = copy.deepcopy(BASE)
    base["trackers"] = [setting]
    base["baselines"], base["dp"] = [], []
    cfg = parse(base)
    s = parse_sweep(dict(GRID), cfg)
    for scheduler in (None, "tcp://127.0.0.1:8786"):
        with pytest.raises(ConfigError, match="has `timeout_s` or `isolate`, which only the sync scheduler honours"):
            run_sweep(cfg, s, tmp_path / "out", scheduler=scheduler)
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_a_worker_with_other_code_stops_the_sweep(tmp_path, monkeypatch):
    real_unit = sw.run_unit
    monkeypatch.setattr(sw, "run_unit", lambda spec: {**real_unit(spec), "source": "0123456789abcdef"})
    cfg, s = _cfg_sweep()
    with pytest.raises(sw.SweepError, match="runs other stripebench code \\(source 0123456789abcdef"):
        run_sweep(cfg, s, tmp_path / "x", scheduler="sync", progress=False, quiet=True)
    assert not list((tmp_path / "x" / "units").glob("*.json"))  # nothing from it is kept


# -- the run-folder guard and the units' integrity ------------------------------------------------------------------

def test_a_sweep_name_never_leaves_the_runs_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("STRIPEBENCH_RUNS", str(tmp_path / "runs"))
    for name in ("../../x", "/etc/x", "a/../../b", ".."):
        cfg = parse({**BASE, "name": name})
        out = sw.default_sweep_dir(cfg, parse_sweep(dict(GRID), cfg))
        assert out.parent == tmp_path / "runs" and "-sweep-" in out.name, (name, out)


def test_a_sweep_into_another_kinds_folder_or_a_locked_one_is_refused(tmp_path):
    from bench.store.runfolder import RunFolder, RunFolderError

    cfg, s = _cfg_sweep()
    with RunFolder(tmp_path / "run") as rf:
        rf.open({"name": "paper"}, "code")
    (tmp_path / "run" / "summary.json").write_text("{}")
    with pytest.raises(RunFolderError, match="holds a run .*not a sweep.*--force"):
        run_sweep(cfg, s, tmp_path / "run", scheduler="sync", progress=False, quiet=True)
    assert (tmp_path / "run" / "summary.json").read_text() == "{}"
    holder = RunFolder(tmp_path / "busy")
    (tmp_path / "busy").mkdir()
    holder.lock()
    try:
        with pytest.raises(RunFolderError, match="is in use by another stripebench process"):
            run_sweep(cfg, s, tmp_path / "busy", scheduler="sync", progress=False, quiet=True)
    finally:
        holder.unlock()


@pytest.mark.slow
def test_damaged_edited_or_misplaced_units_are_recomputed_with_one_line_each(sequential, tmp_path, capsys):
    cfg, s = _cfg_sweep()
    out = tmp_path / "units"
    run_sweep(cfg, s, out, scheduler="sync", chunk=2, progress=False, quiet=True)
    table = _table(out)
    units = sorted((out / "units").glob("*.json"))
    assert len(units) == 3
    units[0].write_text("[]")
    doc = json.loads(units[1].read_text())
    doc["result"]["rows"][0]["hit_rate"] = 0.123  # edited, old checksum kept
    units[1].write_text(json.dumps(doc))
    units[2].unlink()
    units[2].mkdir()
    capsys.readouterr()
    run_sweep(cfg, s, out, scheduler="sync", chunk=2, progress=False, quiet=True)
    err = [line for line in capsys.readouterr().err.splitlines() if "sweep unit" in line]
    assert len(err) == 3 and all("recomputing that unit" in line for line in err)
    assert any("of format 1" in line for line in err) and any("edited or damaged" in line for line in err)
    assert any("a directory, not a file (removed)" in line for line in err)
    pd.testing.assert_frame_equal(_table(out), table)
    assert all(p.is_file() for p in units)
