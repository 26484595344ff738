"""Atomic writes that name their file on any OSError, checksums, format checks, non-files cleared."""

import errno
import os

import numpy as np
import pytest

from bench.store import files
from bench.store.files import (RunFolderError, array_checksum, atomic_write_text, check_format, clear_non_file,
                               json_checksum, non_file_kind, os_error, read_npz)


def test_a_full_disk_during_fsync_names_the_file_not_its_temporary(tmp_path, monkeypatch):
    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")  # as the kernel reports it: no file name

    monkeypatch.setattr(os, "fsync", full)
    target = tmp_path / "metrics.csv"
    with pytest.raises(OSError) as exc:
        atomic_write_text(target, "x")
    assert exc.value.filename == str(target) and exc.value.errno == errno.ENOSPC
    assert str(os_error("write", target, exc.value)) == f"cannot write {str(target)!r}: no space left on the device"
    assert os.listdir(tmp_path) == []  # the temporary file is gone, no old file harmed


def test_a_directory_in_the_files_place_is_an_oserror_naming_it(tmp_path):
    (tmp_path / "summary.json").mkdir()
    with pytest.raises(OSError) as exc:
        atomic_write_text(tmp_path / "summary.json", "{}")
    assert exc.value.filename == str(tmp_path / "summary.json")


def test_checksums_see_every_byte_name_dtype_and_shape():
    a = {"x": np.arange(6.0).reshape(2, 3), "y": np.array("s")}
    base = array_checksum(a)
    assert base == array_checksum(dict(reversed(list(a.items()))))
    assert base != array_checksum({**a, "x": a["x"].reshape(3, 2)})
    assert base != array_checksum({**a, "x": a["x"].astype(np.float32)})
    assert base != array_checksum({"z": a["x"], "y": a["y"]})
    shifted = a["x"].copy()
    shifted[1, 2] += 3.0
    assert base != array_checksum({**a, "x": shifted})
    assert json_checksum({"a": [1.0, float("nan")]}) == json_checksum({"a": [1.0, float("nan")]})
    assert json_checksum({"a": 1}) != json_checksum({"a": 1.0})


def test_check_format_refuses_other_numbers_and_non_numbers(tmp_path):
    assert check_format(np.array(2), (1, 2), "x", tmp_path) == 2
    for bad in (3, "2", True, None, 2.5):
        with pytest.raises(RunFolderError, match="this stripebench reads format 1 or 2"):
            check_format(bad, (1, 2), "x", tmp_path)


def test_non_files_are_named_and_cleared(tmp_path):
    d = tmp_path / "d"
    (d / "sub").mkdir(parents=True)
    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    link = tmp_path / "l"
    link.symlink_to(tmp_path / "nowhere")
    (tmp_path / "file").write_text("x")
    assert [non_file_kind(p) for p in (d, fifo, link, tmp_path / "file", tmp_path / "missing")] == \
        ["a directory", "a FIFO", "a broken link", None, None]
    assert [clear_non_file(p) for p in (d, fifo, link, tmp_path / "file")] == \
        ["a directory", "a FIFO", "a broken link", None]
    assert sorted(os.listdir(tmp_path)) == ["file"]


def test_read_npz_says_why_for_a_directory(tmp_path):
    (tmp_path / "a.npz").mkdir()
    assert read_npz(tmp_path / "a.npz") == (None, "a directory in its place")


def test_docstring_examples():
    import doctest

    assert doctest.testmod(files, extraglobs={"np": np}).failed == 0
