"""Sweep units: a checksum over the result; empty, edited, foreign or misplaced files refused with a reason."""

import json

import pytest

from bench.store.files import json_checksum
from bench.store.sweepfiles import UNIT_FORMAT, read_unit, unit_path, verify_unit, write_unit

RESULT = {"rows": [{"tracker": "dp4", "hit_rate": 0.75, "depth_mae_mm": float("nan")}], "source": "abc",
          "frames": 2, "evaluations": 4, "width": 64, "height": 60, "render_s": 1.5, "eval_s": 0.25,
          "setup_s": 0.1, "first_render_s": 1.0, "host": "h", "pid": 1, "trackers": ["dp4"]}


def test_a_unit_round_trips_with_its_checksum(tmp_path):
    p = unit_path(tmp_path, "f00")
    write_unit(p, RESULT)
    back, why = read_unit(p)
    assert why is None and back["rows"][0]["hit_rate"] == 0.75 and back["frames"] == 2
    doc = json.loads(p.read_text())
    assert doc["format"] == UNIT_FORMAT and doc["checksum"] == json_checksum(doc["result"])
    assert verify_unit(p) is None and read_unit(tmp_path / "none.json") == (None, None)


@pytest.mark.parametrize("text, reason", [
    ("[]", "of format 1"), ("{}", "of format 1"), ("{", "unreadable (JSONDecodeError"),
    (json.dumps(RESULT), "of format 1"),  # the bare result the code before formats wrote
    (json.dumps({"format": 7, "result": RESULT}), "of format 7"),
    (json.dumps({"format": 2, "checksum": json_checksum([]), "result": []}), "damaged (the result is list"),
    (json.dumps({"format": 2, "checksum": json_checksum({}), "result": {}}), "damaged (`rows` missing"),
    (json.dumps({"format": 2, "checksum": json_checksum({**RESULT, "render_s": float("nan")}),
                 "result": {**RESULT, "render_s": float("nan")}}), "damaged (`render_s` is nan"),
    (b"\xff\xfe".decode("latin-1"), "unreadable ("),
])
def test_bad_unit_files_are_refused_with_a_reason(text, reason, tmp_path):
    p = tmp_path / "u.json"
    p.write_text(text, encoding="utf-8" if text.isascii() else "latin-1")
    res, why = read_unit(p)
    assert res is None and why.startswith(reason.split(" (")[0]) and reason in why, why


def test_a_unit_edited_on_disk_is_caught(tmp_path):
    p = tmp_path / "u.json"
    write_unit(p, RESULT)
    doc = json.loads(p.read_text())
    doc["result"]["rows"][0]["hit_rate"] = 0.95
    p.write_text(json.dumps(doc))
    res, why = read_unit(p)
    assert res is None and why.startswith("edited or damaged")


def test_a_directory_in_a_units_place_is_removed_on_request(tmp_path):
    p = tmp_path / "u.json"
    p.mkdir()
    assert read_unit(p) == (None, "a directory, not a file")
    assert read_unit(p, clear_bad=True) == (None, "a directory, not a file (removed)")
    write_unit(p, RESULT)
    assert read_unit(p)[0] is not None
