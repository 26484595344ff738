"""``stripebench trackers`` and ``stripebench scenes`` (bench/cli/info.py)."""

import json

import trackers
from bench.cli import main

def test_trackers_and_scenes_lists(capsys):
    assert main(["trackers"]) == 0
    out = capsys.readouterr().out
    assert "dp8" in out and "threshold" in out and "sub-pixel" in out
    assert main(["scenes"]) == 0
    out = capsys.readouterr().out
    assert "cone" in out and "specular" in out


def test_trackers_json_lists_every_parameter_with_its_default(capsys):
    assert main(["trackers", "--json"]) == 0
    table = {t["name"]: t for t in json.loads(capsys.readouterr().out)}
    assert set(table) == set(trackers.available())
    assert table["dp8"]["params"]["eps"] == trackers.make("dp8").eps
    assert table["threshold"]["subpixel"] is False and table["steger"]["module"] == "trackers.steger"
