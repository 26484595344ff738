"""The sampling procedure's pieces: angles, noise units, the choice and the generated table."""

from pathlib import Path

import numpy as np
import pytest

import scenes
from bench.studies.perf import sampling as S
from bench.cli import main
from bench.studies.perf import sampling_tables as T


def _write(path, results, chosen, argv_text):
    T.write_tables(path, results, chosen, {m: S.choose_objects(results[m]) for m in chosen}, argv_text)


def test_calibration_angles_avoid_the_paper_runs_grid():
    for obj in ("cone", "hand"):
        s = scenes.make(obj, width=64, height=60, cache=False)
        grid = s.object.default_angles(s.rig.zeta_deg, 12)
        angles = S.calibration_angles(s, 3)
        assert len(angles) == 3 and np.all(np.diff(angles) > 0)
        assert np.min(np.abs(angles[:, None] - grid[None, :])) > 0.25 * np.min(np.diff(grid))
        assert grid[0] < angles[0] and angles[-1] < grid[-1]


def test_centroid_sd_matches_a_monte_carlo_of_the_sensor_noise():
    rng = np.random.default_rng(3)
    u = np.arange(31.0)
    laser = 60.0 * np.exp(-0.5 * ((u - 15.3) / 1.5) ** 2)[None, :]
    sigma = np.full((1, 31), 1.7)
    predicted = S.centroid_sd_px(laser, sigma, np.array([15.3]))[0]
    window = slice(10, 21)
    draws = laser[0, window] + rng.normal(0, 1.7, size=(20000, 11))
    c = (draws * u[window]).sum(axis=1) / draws.sum(axis=1)
    assert abs(c.std() / predicted - 1) < 0.05
    assert np.isnan(S.centroid_sd_px(laser, sigma, np.array([np.nan]))[0])
    assert np.isnan(S.centroid_sd_px(laser, sigma, np.array([2.0]))[0])  # window off the image


def test_the_cheapest_qualifying_candidate_is_chosen():
    ok = {"stripe": 0.5, "off": 0.5, "centre": 0.5, "energy": 1.0}
    result = {"laser": {("path", (16,)): {"worst": ok, "cost_s": 0.6, "pass": True},
                        ("path", (4,)): {"worst": {**ok, "centre": 1.5}, "cost_s": 0.1, "pass": False},
                        ("hybrid", (4, 2)): {"worst": ok, "cost_s": 0.3, "pass": True},
                        ("hybrid", (4, 4)): {"worst": ok, "cost_s": 0.4, "pass": True}},
              "ambient": {1: {"z": 1.2, "cost_s": 0.05, "pass": False}, 2: {"z": 0.6, "cost_s": 0.1, "pass": True},
                          4: {"z": 0.4, "cost_s": 0.2, "pass": True}}}
    assert S.choose(result) == (("hybrid", (4, 2)), 2)
    # a pass that more samples lose does not qualify: the next cheapest that does is chosen
    result["laser"][("hybrid", (4, 4))]["pass"] = False
    result["ambient"][4]["pass"] = False
    assert S.choose(result) == (("path", (16,)), None)
    for v in result["laser"].values():
        v["pass"] = False
    assert S.choose(result)[0] is None
    assert S._passes(ok) and not S._passes({**ok, "energy": 1.0 + 2 * S.ENERGY_TOL})
    assert not S._passes({**ok, "off": S.Z_MAX + 0.01})


def test_the_measure_is_zero_on_its_reference_and_sees_a_shifted_stripe():
    u = np.arange(40.0)
    ref = np.repeat((80.0 * np.exp(-0.5 * ((u - 20.2) / 1.4) ** 2))[None, :], 6, axis=0)
    columns = np.full(6, 20.2)
    near = np.abs(u[None, :] - columns[:, None]) <= 3
    m = S._Measure(ref, np.full(ref.shape, 2.0), {"stripe": near, "off": ~near}, columns)
    assert m.lit.all() and m.centroid_sd > 0
    assert m.metrics(ref) == {"stripe": 0.0, "off": 0.0, "energy": 1.0, "centre": 0.0}
    shifted = np.roll(ref, 1, axis=1)
    out = m.metrics(shifted)
    assert out["centre"] > 1 and out["stripe"] > 1 and out["off"] > 0
    dim = m.metrics(0.5 * ref)
    assert dim["energy"] == 0.5 and dim["centre"] < 1e-9


def test_each_objects_count_is_the_cheapest_qualifying_one():
    ok = {"stripe": 0.5, "off": 0.5, "centre": 0.5, "energy": 1.0}
    bad = {**ok, "stripe": 3.0}
    result = {"object": {"cone/none-table": {("path", (n,)): {"worst": ok, "cost_s": n / 10, "pass": True}
                                             for n in (2, 4, 8, 16)},
                         "hand/none-table": {("path", (n,)): {"worst": bad, "cost_s": n / 10, "pass": False}
                                             for n in (2, 4, 8, 16)}}}
    result["object"]["cone/none-table"][("path", (2,))].update(worst=bad, **{"pass": False})
    assert S.choose_objects(result) == {"cone/none-table": 4, "hand/none-table": None}
    result["object"]["cone/none-table"][("path", (8,))]["pass"] = False  # lost by more samples: not a margin
    assert S.choose_objects(result)["cone/none-table"] == 16
    assert S.choose_objects({"laser": {}}) == {}
    # fewer samples in every pass is cheaper, whatever the measured seconds say
    result["object"]["cone/none-table"][("path", (8,))]["pass"] = True
    result["object"]["cone/none-table"][("path", (4,))]["cost_s"] = 9.0
    assert S.choose_objects(result)["cone/none-table"] == 4
    laser = {("split_hybrid", (16, 2, 2)): {"cost_s": 0.46, "pass": True},
             ("split_hybrid", (16, 4, 2)): {"cost_s": 0.42, "pass": True},
             ("split_hybrid", (16, 2, 4)): {"cost_s": 0.52, "pass": True},
             ("split", (16, 16)): {"cost_s": 0.40, "pass": True}}
    assert S._cheapest(laser) == ("split", (16, 16))  # other integrators: the measured cost decides
    del laser[("split", (16, 16))]
    assert S._cheapest(laser) == ("split_hybrid", (16, 2, 2))


def test_saved_measurements_choose_and_write_without_rendering(tmp_path, capsys):
    ok = {"stripe": 0.5, "off": 0.4, "centre": 0.3, "energy": 0.999}
    results = {m: {"laser": {("path", (8,)): {"worst": ok, "cost_s": 0.3, "pass": True}},
                   "ambient": {2: {"z": 0.6, "cost_s": 0.1, "pass": True}}, "cases": ["a"], "checks": []}
               for m in S.MATERIALS}
    saved = {"format": 1, "options": {"angles": 2, "ref_spp": 144, "ref_ambient_spp": 144},
             "results": {m: T.to_json(r) for m, r in results.items()}}
    path = tmp_path / "m.json"
    import json
    path.write_text(json.dumps(saved))
    assert T.from_json(T.to_json(results["matte"]))["laser"] == results["matte"]["laser"]
    assert main(["perf", "sampling", "--from", str(path)]) == 0
    out = capsys.readouterr().out
    assert "| `specular` | path 8 | 2 |" in out
    bad = tmp_path / "bad.json"
    bad.write_text("{}")
    assert main(["perf", "sampling", "--from", str(bad)]) == 2
    assert "not a file of `stripebench perf sampling --save`" in capsys.readouterr().err


def test_write_replaces_only_the_generated_block(tmp_path):
    src = Path(scenes.sampling.__file__).read_text()
    path = tmp_path / "sampling.py"
    path.write_text(src)
    ok = {"stripe": 0.5, "off": 0.4, "centre": 0.3, "energy": 0.999}
    results = {"matte": {"laser": {("hybrid", (4, 2)): {"worst": ok, "cost_s": 0.3, "pass": True}},
                         "ambient": {2: {"z": 0.6, "cost_s": 0.1, "pass": True}}, "cases": ["a", "b"]},
               "specular": {"laser": {}, "ambient": {}, "cases": ["c"]}}
    _write(path, results, {"matte": (("hybrid", (4, 2)), 2), "specular": (None, None)}, "cmd")
    text = path.read_text()
    before, after = src.split("# --- generated: begin ---\n"), text.split("# --- generated: begin ---\n")
    assert before[0] == after[0] and before[1].split("# --- generated: end ---\n")[1] == \
        after[1].split("# --- generated: end ---\n")[1]
    ns = {}
    exec(after[1].split("# --- generated: end ---\n")[0], ns)
    assert ns["LASER_KIND"] == {"matte": "hybrid"} and ns["LASER_SPP"] == {"matte": (4, 2)}
    assert ns["AMBIENT_SPP"] == {"matte": 2} and ns["MEASURED"]["matte"]["cases"] == 2
    assert ns["OBJECT_SPP"] == {} and ns["MEASURED_OBJECT"] == {}
    # a shiny material: the counts certified per object, and the numbers of each object's count
    bad = {**ok, "stripe": 4.0}
    results["polished"] = {
        "laser": {("split_hybrid", (16, 2, 2)): {"worst": ok, "cost_s": 0.7, "pass": True}},
        "ambient": {2: {"z": 0.6, "cost_s": 0.1, "pass": True}}, "cases": ["a", "b"],
        "object": {"cone/none-table": {("path", (n,)): {"worst": ok, "cost_s": n, "pass": True} for n in (4, 16)},
                   "hand/none-table": {("path", (n,)): {"worst": bad, "cost_s": n, "pass": False} for n in (4, 16)}}}
    _write(path, results, {"matte": (("hybrid", (4, 2)), 2), "specular": (None, None),
                             "polished": (("split_hybrid", (16, 2, 2)), 2)}, "cmd")
    ns = {}
    exec(path.read_text().split("# --- generated: begin ---\n")[1].split("# --- generated: end ---\n")[0], ns)
    assert ns["OBJECT_SPP"] == {"polished": {"cone/none-table": 4}}
    assert ns["MEASURED_OBJECT"]["polished"]["cone/none-table"]["spp"] == 4
    hand = ns["MEASURED_OBJECT"]["polished"]["hand/none-table"]
    assert hand["spp"] == scenes.sampling.FIXED_SPP and not hand["certified"] and hand["z_stripe"] == 4.0
    back = T.from_json(T.to_json(results["polished"]))
    assert back["object"] == results["polished"]["object"]


def test_bad_options_are_one_line_errors(capsys):
    assert main(["perf", "sampling", "--materials", "chrome"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--materials must name some of matte" in err and "'chrome'" in err


def test_write_needs_every_material(capsys):
    assert main(["perf", "sampling", "--materials", "matte", "--write"]) == 2
    assert "--write needs every one of matte, patchy" in capsys.readouterr().err


@pytest.mark.slow
def test_a_shiny_materials_measurement_has_its_objects_passes(monkeypatch):
    # the procedure on tiny frames (its renders and bookkeeping, not its numbers): every laser
    # candidate and, per object on its geometry, every object count, each with its metrics
    real_make = scenes.make
    monkeypatch.setattr(scenes, "make", lambda *a, **k: real_make(*a, **{**k, "width": 64, "height": 60}))
    monkeypatch.setattr(S, "OBJECT_SPP", (1, 2))
    monkeypatch.setattr(S, "laser_candidates", lambda m: [("split_hybrid", (2, 1, 1))])
    monkeypatch.setattr(S, "AMBIENT_CANDIDATES", (1,))
    result = S.measure("polished", 1, 2, 2, progress=False, ref_object_spp=4)
    assert list(result["laser"]) == [("split_hybrid", (2, 1, 1))] and list(result["ambient"]) == [1]
    assert set(result["object"]) == {"cone/none-table", "hand/none-table"}
    for cands in result["object"].values():
        assert list(cands) == [("path", (1,)), ("path", (2,))]
        for rec in cands.values():
            assert set(rec["worst"]) == {"stripe", "off", "centre", "energy"} and rec["cost_s"] >= 0
            assert all(np.isfinite(v) for v in rec["worst"].values()) and isinstance(rec["pass"], bool)
    assert set(S.choose_objects(result)) == {"cone/none-table", "hand/none-table"}
    back = T.from_json(T.to_json(result))
    assert back["object"] == result["object"]
