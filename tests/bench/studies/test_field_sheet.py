"""The field profile's contact sheet (bench.studies.field_sheet): its plain function on a tiny configuration."""

import tomllib

import numpy as np
import pytest

from bench.config import parse
from bench.studies import field_sheet as F

# one colour-camera experiment of the field profile, at a tiny size and sample count
_TINY = """
name = "tiny-field"
seed = 0
trackers = ["threshold"]
baselines = []
dp = []
[render]
width = 32
height = 30
spp = 1
ambient_spp = 1
[[experiments]]
name = "tiny"
condition = "turntable-saturated"
scene = "sphere"
material = "matte"
camera = "rgb"
filter = "none"
"""


def test_the_sheet_of_a_tiny_configuration_is_written(tmp_path, capsys):
    config = parse(tomllib.loads(_TINY))
    out = tmp_path / "sheet.png"
    assert F.sheet(out, config=config) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and capsys.readouterr().out.strip() == f"wrote {out}"
    import matplotlib.image

    img = matplotlib.image.imread(out)
    assert img.ndim == 3 and img.shape[1] > img.shape[0] > 100  # four columns of one row, titled


def test_the_sheet_must_be_a_png_file(tmp_path, capsys):
    assert F.sheet(tmp_path / "sheet.jpg") == 2
    assert capsys.readouterr().err.strip() == f"stripebench: `out` must be a .png file, got {str(tmp_path / 'sheet.jpg')!r}"
    assert not (tmp_path / "sheet.jpg").exists()


def test_the_contact_sheet_titles_each_frame_with_its_condition(tmp_path):
    class E:
        condition, key, scene, material = "daylit", "k", "cone", "patchy"

    class Frame:
        rgb, image = None, np.full((30, 32), 128, np.uint8)

    path = F.contact_sheet([(E(), Frame())] * 2, tmp_path / "s.png", columns=2)
    assert path.exists() and path.stat().st_size > 1000
