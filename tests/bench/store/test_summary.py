"""summary.json of every kind: one builder, one validator, formats and kinds checked."""

import json

import pytest

from bench.store import summary as S
from bench.store.files import RunFolderError

RUN = {"config": {"render": {}, "experiments": []}, "seed": 0, "improvement": [], "scans": [],
       "git_revision": "abc", "paper_improvement": 0.3, "variants": [], "versions": {}}


def test_the_builder_puts_format_and_kind_first_and_checks_the_fields():
    doc = S.build_summary("run", **RUN, wall_s=1.0)
    with pytest.raises(ValueError, match="`wall_s` missing"):  # the report's provenance reads it
        S.build_summary("run", **RUN)
    assert list(doc)[:3] == ["format", "kind", "config"] and doc["format"] == S.FORMAT
    with pytest.raises(ValueError, match="`scans` missing"):
        S.build_summary("run", **{k: v for k, v in RUN.items() if k != "scans"}, wall_s=1.0)
    with pytest.raises(ValueError, match="`seed` missing or not an int"):
        S.build_summary("run", **{**RUN, "seed": True}, wall_s=1.0)
    with pytest.raises(TypeError, match="not JSON serialisable"):
        S.build_summary("run", **RUN, wall_s=1.0, extra=object())


def test_the_reader_accepts_format_1_and_refuses_newer_or_other_kinds(tmp_path):
    p = tmp_path / "summary.json"
    p.write_text(json.dumps({**RUN, "wall_s": 1.0}))  # format 1: no format, no kind: a synthetic run
    assert S.summary_kind(S.read_summary(p)) == "run"
    p.write_text(json.dumps({**RUN, "wall_s": 1.0, "format": 3}))
    with pytest.raises(RunFolderError, match="run summary of format 3; this stripebench reads format 1 or 2"):
        S.read_summary(p)
    real = S.build_summary("real", config={}, seed=0, trackers={}, n_images=1, tol_px=3.0)
    S.write_summary(p, real)
    with pytest.raises(RunFolderError, match="is the summary of a real, not of a sweep"):
        S.read_summary(p, kind="sweep")
    assert S.read_summary(p, kind=("run", "real"))["kind"] == "real"


@pytest.mark.parametrize("text, message", [("{", "is not valid JSON"), ("[1]", "a JSON object"),
                                           ('{"kind": "nope", "format": 2}', "`kind` is 'nope'"),
                                           ("[" * 100000 + "]" * 100000, "is nested too deeply")])
def test_bad_summaries_are_one_line(text, message, tmp_path):
    p = tmp_path / "summary.json"
    p.write_text(text)
    with pytest.raises(RunFolderError, match=message) as exc:
        S.read_summary(p)
    assert "\n" not in str(exc.value) and str(p) in str(exc.value)


def test_docstring_examples():
    import doctest

    assert doctest.testmod(S).failed == 0
