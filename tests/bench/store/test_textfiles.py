"""Safe document readers (bench/store/textfiles.py): regular files only, UTF-8, bounded nesting and integers."""

import os

import pytest

from bench.errors import ConfigError, InputError
from bench.store import textfiles as T


def test_a_regular_utf8_file_is_read(tmp_path):
    p = tmp_path / "a.toml"
    p.write_text("x = 'é'\n", encoding="utf-8")
    assert T.read_toml_file(p) == {"x": "é"}


def test_a_fifo_a_folder_and_a_device_are_refused_without_blocking(tmp_path):
    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r"'.*f' is not a regular file \(a FIFO\)"):
        T.read_text(fifo, "configuration")
    with pytest.raises(InputError, match=r"is not a regular file \(a folder\)"):
        T.read_text(tmp_path)
    with pytest.raises(InputError, match=r"is not a regular file \(a character device\)"):
        T.read_text("/dev/zero")


def test_missing_large_and_non_utf8_files(tmp_path):
    with pytest.raises(ConfigError, match=r"cannot read configuration '.*nope': no such file"):
        T.read_text(tmp_path / "nope", "configuration", error=ConfigError)
    big = tmp_path / "big"
    big.write_bytes(b"x" * 100)
    with pytest.raises(InputError, match="is too large"):
        T.read_text(big, max_bytes=10)
    bad = tmp_path / "bad"
    bad.write_bytes(b"ok \xff")
    with pytest.raises(InputError, match=r"is not UTF-8 text \(byte 3: b'\\xff'\)"):
        T.read_text(bad)


@pytest.mark.parametrize("text", ["[" * 100000 + "]" * 100000, '{"a":' * 5000 + "1" + "}" * 5000,
                                  "[" * (T.MAX_DEPTH + 1) + "]" * (T.MAX_DEPTH + 1)])
def test_deep_json_is_refused(text):
    with pytest.raises(InputError, match="nested too deeply"):
        T.loads_json(text, "doc")


def test_json_at_the_depth_limit_and_huge_integers():
    ok = "[" * T.MAX_DEPTH + "]" * T.MAX_DEPTH
    assert T.loads_json(ok, "doc") is not None
    assert T.loads_json(str(2**63 - 1), "doc") == 2**63 - 1
    for big in ("1" + "0" * 400, str(2**63), "-" + "9" * 5000):
        with pytest.raises(InputError, match="holds an integer of"):
            T.loads_json(f"[{big}]", "doc")
    with pytest.raises(InputError, match="is not valid JSON"):
        T.loads_json("{nope", "doc")


@pytest.mark.parametrize("text", ["a = " + "[" * 5000 + "]" * 5000, "a = " + "{b = " * 5000 + "1" + "}" * 5000,
                                  "a = " + "[" * (T.MAX_DEPTH + 1) + "]" * (T.MAX_DEPTH + 1)])
def test_deep_toml_is_refused(text):
    with pytest.raises(InputError, match="nested too deeply"):
        T.loads_toml(text, "c.toml")


def test_toml_integers_beyond_64_bits_and_invalid_toml():
    for big in ("1" + "0" * 400, "9" * 5000):
        with pytest.raises(InputError, match="c.toml"):
            T.loads_toml(f"x = {big}", "c.toml")
    with pytest.raises(InputError, match="c.toml: invalid TOML"):
        T.loads_toml("x = ", "c.toml")
