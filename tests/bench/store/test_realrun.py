"""Outputs of `track` and `real`: names that cannot collide, inputs never inside the output folder."""

import pytest

from bench.store import realrun
from bench.store.files import RunFolderError
from bench.store.realrun import track_output_names, write_inputs


def test_distinct_stems_name_their_outputs(tmp_path):
    names = track_output_names([tmp_path / "a" / "x.png", tmp_path / "b" / "y.jpg"], tmp_path / "out")
    assert sorted(names.values()) == ["x", "y"]


@pytest.mark.parametrize("inputs", [("a/same.png", "b/same.png"), ("dup.png", "dup.jpg")])
def test_two_inputs_with_one_stem_are_refused(inputs, tmp_path):
    with pytest.raises(RunFolderError, match="would both write .*; track them into separate --out folders") as exc:
        track_output_names([tmp_path / p for p in inputs], tmp_path / "out")
    assert all(p.split("/")[-1] in str(exc.value) for p in inputs) and "\n" not in str(exc.value)


def test_an_input_inside_the_output_folder_is_refused_even_with_force(tmp_path):
    for inp, extra in ((tmp_path / "x.png", []), (tmp_path / "sub" / "x.png", []),
                       (tmp_path / "elsewhere.png", [tmp_path / "bg.png"])):
        with pytest.raises(RunFolderError, match="is inside the output folder"):
            track_output_names([inp], tmp_path, extra_inputs=extra, force=True)


def test_a_name_written_for_another_input_is_refused_without_force(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    write_inputs(out, {"same": str((tmp_path / "a" / "same.png").resolve())})
    assert track_output_names([tmp_path / "a" / "same.png"], out)  # the same input again: fine
    with pytest.raises(RunFolderError, match="was written for .*pass --force to replace it"):
        track_output_names([tmp_path / "b" / "same.png"], out)
    assert track_output_names([tmp_path / "b" / "same.png"], out, force=True)


def test_docstring_examples():
    import doctest

    assert doctest.testmod(realrun).failed == 0
