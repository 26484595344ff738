import pytest

from scenes import contact_sheet

pytestmark = pytest.mark.slow


def test_contact_sheet_writes_a_png(tmp_path, capsys):
    out = tmp_path / "sheet.png"
    assert contact_sheet.main([str(out), "--width", "64", "--height", "60", "--objects", "cone",
                               "--materials", "matte", "specular", "--dpi", "30"]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert str(out) in capsys.readouterr().out


def test_contact_sheet_rejects_unknown_names(tmp_path):
    with pytest.raises(SystemExit):
        contact_sheet.main([str(tmp_path / "x.png"), "--materials", "velvet"])
