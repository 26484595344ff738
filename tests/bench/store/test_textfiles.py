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


def test_loads_csv_reads_what_spreadsheets_write():
    from bench.store.textfiles import loads_csv

    text = '\ufeffa,b\r\n1,"x\u2028y"\r\n2,"p\u0085q\u2029r"\n3,"line\r\nbreak"\n'
    cols, rows = loads_csv(text, "t.csv")
    assert cols == ["a", "b"] and [r["a"] for r in rows] == ["1", "2", "3"]
    assert rows[0]["b"] == "x\u2028y" and rows[1]["b"] == "p\u0085q\u2029r" and rows[2]["b"] == "line\r\nbreak"
    assert loads_csv("a,b\n1,2\n", "t.csv", header=False) == [["a", "b"], ["1", "2"]]


def test_loads_csv_bounds_a_field_and_names_the_file():
    import pytest

    from bench.errors import InputError
    from bench.store.textfiles import MAX_CSV_FIELD, loads_csv

    ok = loads_csv('a\n"' + "x" * MAX_CSV_FIELD + '"\n', "t.csv")[1]
    assert len(ok[0]["a"]) == MAX_CSV_FIELD
    with pytest.raises(InputError, match=r"^t\.csv: not a readable CSV table \(a field is longer than 16,777,216"):
        loads_csv('a\n"' + "x" * (MAX_CSV_FIELD + 1) + '"\n', "t.csv")
