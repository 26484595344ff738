"""Real photographs: readers, channels, rotation, pairing, the real-set validator,
per-image metrics and the sim-to-real comparison."""

import csv

import imageio.v3 as iio
import numpy as np
import pandas as pd
import pytest
import tifffile

from bench.store import realset as real


def _write_set(root, images, *, manifest=None):
    """A tiny real set: images = {name: (on, off or None, ref or None, laser)}."""
    root.mkdir(parents=True, exist_ok=True)
    rows = []
    for name, (on, off, ref, laser) in images.items():
        iio.imwrite(root / f"{name}.png", on)
        if off is not None:
            iio.imwrite(root / f"{name}_off.png", off)
        if ref is not None:
            lines = ["row,col"] + [f"{i}," + ("" if np.isnan(c) else f"{c}") for i, c in enumerate(ref)]
            (root / f"{name}_ref.csv").write_text("\n".join(lines) + "\n")
        rows.append({"name": name, "has_background": int(off is not None), "laser_colour": laser})
    with open(root / "manifest.csv", "w", newline="") as f:
        cols = manifest or ["name", "has_background", "laser_colour"]
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    return root


def _stripe(h=20, w=30, col=12, value=200, colour=None):
    img = np.full((h, w), 10, np.uint8)
    img[:, col] = value
    if colour is None:
        return img
    rgb = np.repeat(img[..., None], 3, axis=2)
    rgb[:, col] = colour
    return rgb


# ---------------------------------------------------------------------------------------------------- readers


def test_read_grey_rgb_rgba_16bit_png_tiff_and_jpeg(tmp_path):
    grey = _stripe()
    iio.imwrite(tmp_path / "g.png", grey)
    assert real.read_image(tmp_path / "g.png").dtype == np.uint8
    np.testing.assert_array_equal(real.read_image(tmp_path / "g.png"), grey)
    rgb = _stripe(colour=(220, 30, 40))
    iio.imwrite(tmp_path / "c.png", rgb)
    np.testing.assert_array_equal(real.read_image(tmp_path / "c.png"), rgb)
    rgba = np.concatenate([rgb, np.full(rgb.shape[:2] + (1,), 255, np.uint8)], axis=2)
    iio.imwrite(tmp_path / "a.png", rgba)
    np.testing.assert_array_equal(real.read_image(tmp_path / "a.png"), rgb)
    g16 = grey.astype(np.uint16) * 257
    iio.imwrite(tmp_path / "g16.png", g16)
    out = real.read_image(tmp_path / "g16.png")
    assert out.dtype == np.uint16 and int(out.max()) == 200 * 257
    tifffile.imwrite(tmp_path / "c16.tif", rgb.astype(np.uint16) * 257)
    out = real.read_image(tmp_path / "c16.tif")
    assert out.dtype == np.uint16 and out.shape == rgb.shape and int(out[0, 12, 0]) == 220 * 257
    wide = rgb.copy()
    wide[:, 8:17] = (220, 30, 40)  # JPEG's chroma subsampling smears a 1-px colour line
    iio.imwrite(tmp_path / "c.jpg", wide, quality=95)
    out = real.read_image(tmp_path / "c.jpg")
    assert out.shape == rgb.shape and out.dtype == np.uint8 and abs(int(out[5, 12, 0]) - 220) < 20


def test_bmp_frames_grey_palette_and_colour_are_read_as_their_pixels(tmp_path):
    """A machine-vision camera's or MATLAB's BMP: 8-bit grey (mode L), 8-bit with a grey palette (read as RGB with
    three equal channels, which the channels take for grey) and 24-bit colour, each read as its pixels."""
    from PIL import Image

    rng = np.random.default_rng(2)
    grey = rng.integers(0, 256, (6, 10), dtype=np.uint8)
    Image.fromarray(grey, "L").save(tmp_path / "g.bmp")
    np.testing.assert_array_equal(real.read_image(tmp_path / "g.bmp"), grey)
    pal = Image.fromarray(grey, "L").convert("P")
    pal.putpalette([v for i in range(256) for v in (i, i, i)])
    pal.save(tmp_path / "p.bmp")
    out = real.read_image(tmp_path / "p.bmp")
    assert out.shape in ((6, 10), (6, 10, 3))
    np.testing.assert_array_equal(real.select_channel(out, "auto"), grey)
    rgb = rng.integers(0, 256, (6, 10, 3), dtype=np.uint8)
    Image.fromarray(rgb, "RGB").save(tmp_path / "c.bmp")
    np.testing.assert_array_equal(real.read_image(tmp_path / "c.bmp"), rgb)
    assert real.background_for(tmp_path / "c.bmp") is None
    Image.fromarray(rgb, "RGB").save(tmp_path / "c_off.bmp")
    assert real.background_for(tmp_path / "c.bmp") == tmp_path / "c_off.bmp"


@pytest.mark.parametrize("content, suffix, message", [
    (b"not an image at all", ".png", "cannot read image"),
    (b"", ".jpg", "cannot read image"),
    (None, ".png", "no such file"),
    (b"x", ".gif", "not a PNG, JPEG, TIFF or BMP file"),
])
def test_bad_files_raise_one_line(tmp_path, content, suffix, message):
    p = tmp_path / f"bad{suffix}"
    if content is not None:
        p.write_bytes(content)
    with pytest.raises(real.ImageError, match=message) as err:
        real.read_image(p)
    assert "\n" not in str(err.value)


def test_channels_on_a_colour_pixel():
    px = np.array([[[200, 100, 50]]], dtype=np.uint8)
    assert int(real.select_channel(px, "r")[0, 0]) == 200
    assert int(real.select_channel(px, "b")[0, 0]) == 50
    assert real.select_channel(px, "gray")[0, 0] == pytest.approx(0.2126 * 200 + 0.7152 * 100 + 0.0722 * 50)
    assert real.select_channel(px, "excess", "red")[0, 0] == pytest.approx(200 - 75)
    assert real.select_channel(px, "excess", "green")[0, 0] == 0.0  # 100 - 125 clipped
    assert real.select_channel(px, "excess", "blue")[0, 0] == 0.0
    # unsaturated colour pixels: auto is the excess
    np.testing.assert_array_equal(real.select_channel(px, "auto", "green"), real.select_channel(px, "excess", "green"))
    grey_rgb = np.repeat(np.array([[7, 9]], np.uint8)[..., None], 3, axis=2)
    assert real.select_channel(grey_rgb, "auto").tolist() == [[7, 9]]  # not the all-zero excess
    u16 = px.astype(np.uint16) * 257
    assert real.select_channel(u16, "g").dtype == np.uint16


def test_grey_image_is_its_own_channel_and_bad_names_are_refused():
    g = _stripe()
    for ch in real.CHANNELS:
        assert real.select_channel(g, ch) is g
    with pytest.raises(ValueError, match="`channel` must be one of"):
        real.select_channel(g, "red")
    with pytest.raises(ValueError, match="`laser` must be one of"):
        real.select_channel(g, "r", "yellow")


@pytest.mark.parametrize("rot", [0, 90, 180, 270])
def test_unrotate_points_inverts_rotate_image(rot):
    rng = np.random.default_rng(rot)
    img = np.zeros((7, 11))
    rr, cc = rng.integers(0, 7, 5), rng.integers(0, 11, 5)
    img[rr, cc] = 1
    r, c = np.nonzero(real.rotate_image(img, rot))
    r0, c0 = real.unrotate_points(r, c, rot, img.shape)
    assert set(zip(r0.astype(int), c0.astype(int))) == set(zip(rr, cc))
    with pytest.raises(ValueError, match="`rotate_deg` must be one of"):
        real.rotate_image(img, 45)


def test_background_pairing_by_name(tmp_path):
    iio.imwrite(tmp_path / "a.png", _stripe())
    iio.imwrite(tmp_path / "a_off.png", _stripe(value=10))
    iio.imwrite(tmp_path / "b.png", _stripe())
    iio.imwrite(tmp_path / "c.jpg", _stripe(colour=(200, 0, 0)))
    iio.imwrite(tmp_path / "c_off.png", _stripe(value=10))
    assert real.background_for(tmp_path / "a.png") == tmp_path / "a_off.png"
    assert real.background_for(tmp_path / "b.png") is None
    assert real.background_for(tmp_path / "c.jpg") == tmp_path / "c_off.png"


# ---------------------------------------------------------------------------------------------------- the real set


def test_a_valid_set_loads(tmp_path):
    ref = np.full(20, 12.0)
    ref[:3] = np.nan
    root = _write_set(tmp_path / "set", {"one": (_stripe(), _stripe(value=10), ref, "red"),
                                         "two": (_stripe(colour=(0, 250, 0)), None, np.full(20, 12.0), "green")})
    images, problems = real.validate_dataset(root)
    assert problems == [] and [i.name for i in images] == ["one", "two"]
    frame, bg, original, r = images[0].load()
    assert frame.shape == (20, 30) and bg is not None and np.isnan(r[:3]).all() and r[5] == 12.0
    frame, bg, _, _ = images[1].load()
    assert bg is None and frame[0, 12] == 250.0 and frame[0, 0] == 0.0  # green minus the mean of red and blue


def test_validator_gives_one_line_per_problem(tmp_path):
    good = np.full(20, 12.0)
    root = _write_set(tmp_path / "set", {
        "noref": (_stripe(), None, None, "red"),
        "short": (_stripe(), None, good[:15], "red"),
        "offshape": (_stripe(), _stripe(h=19), good, "red"),
        "laser": (_stripe(), None, good, "purple"),
        "fine": (_stripe(), None, good, "red"),
    })
    (root / "stray_off.png").write_bytes(b"")  # not in the manifest: ignored
    images, problems = real.validate_dataset(root)
    assert [i.name for i in images] == ["fine"]
    assert len(problems) == 4
    assert any(p == "noref: missing reference noref_ref.csv" for p in problems)
    assert any(p.startswith("short_ref.csv: 15 rows for an image of height 20") for p in problems)
    assert any(p.startswith("offshape: offshape_off.png has shape (19, 30)") for p in problems)
    assert any("laser_colour must be one of red, green, blue, got 'purple'" in p for p in problems)
    with pytest.raises(real.DatasetError) as err:
        real.load_dataset(root)
    assert err.value.problems == problems


@pytest.mark.parametrize("text, message", [
    ("name,laser_colour\na,red\n", "manifest.csv: missing column(s) has_background"),
    ("name,has_background,laser_colour\n", "manifest.csv: no images listed"),
    (None, "no manifest.csv (not a real set)"),
])
def test_bad_manifest_is_one_line(tmp_path, text, message):
    if text is not None:
        (tmp_path / "manifest.csv").write_text(text)
    images, problems = real.validate_dataset(tmp_path)
    assert images == [] and len(problems) == 1 and message in problems[0]


@pytest.mark.parametrize("body, message", [
    ("row,col\n0,1\n1,x\n", "line 3: col must be a number or empty, got 'x'"),
    ("row,col\n0,1\n2,1\n", "line 3: rows must run 0..1 in order, got 2"),
    ("row,col\n0,1\n1,30\n", "line 3: col must lie in [-0.5, 29.5], got '30'"),
    ("r,c\n0,1\n1,1\n", "header must be 'row,col' or 'row,col,state'"),
    ("row,col,state\n0,1,stripe\n1,,maybe\n", "line 3: state must be one of stripe, none, unknown, got 'maybe'"),
    ("row,col,state\n0,1,stripe\n1,,stripe\n", "line 3: a 'stripe' row must have a col, got ''"),
    ("row,col,state\n0,1,none\n1,,none\n", "line 2: a 'none' row must not have a col, got '1'"),
    ("row,col,state\n0,1,stripe\n1,\n", "line 3: expected 3 fields"),
])
def test_reference_errors_name_the_line(tmp_path, body, message):
    p = tmp_path / "x_ref.csv"
    p.write_text(body)
    with pytest.raises(real.DatasetError, match=message.replace("[", r"\[").replace("]", r"\]")):
        real.read_reference(p, (2, 30))


def test_reference_states_explicit_and_by_the_fallback(tmp_path):
    from bench.evaluate.outcomes import NO_STRIPE, STRIPE, UNSURE

    p = tmp_path / "x_ref.csv"
    p.write_text("row,col,state\n0,3.5,stripe\n1,,unknown\n2,,none\n")
    cols, states, explicit = real.read_reference_states(p, (3, 30))
    assert explicit and states.tolist() == [STRIPE, UNSURE, NO_STRIPE] and cols[0] == 3.5 and np.isnan(cols[1:]).all()
    assert np.array_equal(real.read_reference(p, (3, 30)), cols, equal_nan=True)
    q = tmp_path / "y_ref.csv"  # no state column: rows without a column 2 or more rows from one have no stripe
    q.write_text("row,col\n0,4\n1,\n2,\n3,\n")
    cols, states, explicit = real.read_reference_states(q, (4, 30), gap_rows=2)
    assert not explicit and states.tolist() == [STRIPE, UNSURE, NO_STRIPE, NO_STRIPE]


def test_the_shipped_set_is_valid():
    images, problems = real.validate_dataset(real.SHIPPED)
    assert problems == []
    assert len(images) >= 12
    assert len({im.meta["source_repo"] for im in images}) >= 3
    assert all(im.meta["license"] and im.meta["source_commit"] and im.meta["notes"] for im in images)


def test_synthetic_hit_rates_read_the_object_region(tmp_path):
    pd.DataFrame({"experiment": ["e1", "e2", "e1", "e2", "e1"], "tracker": ["t", "t", "u", "u", "t"],
                  "region": ["object", "object", "object", "object", "all"],
                  "hit_rate": [0.2, 0.4, 1.0, 0.5, 0.9]}).to_parquet(tmp_path / "metrics.parquet")
    assert real.synthetic_hit_rates(tmp_path) == {"t": pytest.approx(0.3), "u": pytest.approx(0.75)}


def test_docstring_examples_run():
    import doctest

    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(real, extraglobs={"np": np}, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0


def test_extra_manifest_columns_are_ignored_and_listed(tmp_path):
    import shutil

    for f in real.SHIPPED.iterdir():
        if f.name.startswith("ag_tape"):
            shutil.copy(f, tmp_path / f.name)
    text = (real.SHIPPED / "manifest.csv").read_text().splitlines()
    head, row = text[0], next(line for line in text if line.startswith("ag_tape,"))
    (tmp_path / "manifest.csv").write_text(f"{head},surface,rows\n{row},paper,480\n")
    images, problems = real.validate_dataset(tmp_path)
    assert problems == [] and [im.name for im in images] == ["ag_tape"]
    assert real.ignored_columns(tmp_path) == ["surface", "rows"]
    assert real.ignored_columns(real.SHIPPED) == []
    (tmp_path / "manifest.csv").write_text("name,laser_colour,surface\nag_tape,red,paper\n")
    assert "missing column(s) has_background" in real.validate_dataset(tmp_path)[1][0]  # still required


def test_the_condition_column_is_read_not_ignored(tmp_path):
    path = tmp_path / "manifest.csv"
    _write_set(tmp_path, {"a": (_stripe(), None, np.full(20, 12.0), "red"),
                          "b": (_stripe(), None, np.full(20, 12.0), "red")})
    path.write_text("name,has_background,laser_colour,condition\na,0,red,turntable-saturated\nb,0,red,\n")
    images = {im.name: im for im in real.load_dataset(tmp_path)}
    assert images["a"].meta["condition"] == "turntable-saturated" and images["b"].meta["condition"] == ""
    assert real.ignored_columns(tmp_path) == []
    shipped = {im.name: im.meta["condition"] for im in real.load_dataset(real.SHIPPED)}
    assert all(shipped.values()), "every shipped photograph carries a class"


def _png16_rgb(h: int, w: int, value: int) -> bytes:
    """A 16-bit RGB PNG written by hand (Pillow cannot write one)."""
    import struct
    import zlib

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    row = b"\x00" + struct.pack(">H", value) * (3 * w)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(row * h)) + chunk(b"IEND", b""))


def test_cmyk_16_bit_colour_png_and_multi_page_tiff(tmp_path):
    from PIL import Image

    rgb = np.zeros((6, 8, 3), np.uint8)
    rgb[:, 3] = (250, 20, 10)
    Image.fromarray(rgb).convert("CMYK").save(tmp_path / "c.jpg", quality=100)
    back = real.read_image(tmp_path / "c.jpg")  # converted to RGB, not read as 4 channels
    assert back.shape == (6, 8, 3) and back[:, 3, 0].min() > 200 and back[:, 0].max() < 40
    (tmp_path / "d.png").write_bytes(_png16_rgb(6, 8, 40000))  # refused, not read as zeros
    with pytest.raises(real.ImageError, match="a 16-bit colour PNG is not supported"):
        real.read_image(tmp_path / "d.png")
    with tifffile.TiffWriter(tmp_path / "two.tif") as w:
        w.write(np.zeros((6, 8), np.uint16))
        w.write(np.ones((6, 8), np.uint16))
    with pytest.raises(real.ImageError, match=r"a multi-page TIFF \(2 pages\); give one frame per file"):
        real.read_image(tmp_path / "two.tif")
    tifffile.imwrite(tmp_path / "one.tif", np.full((6, 8), 7, np.uint16))
    assert real.read_image(tmp_path / "one.tif").dtype == np.uint16


def test_manifest_and_reference_as_spreadsheets_write_them(tmp_path):
    """A UTF-8 byte-order mark, CRLF rows, a U+2028 / U+0085 inside a quoted notes cell and a long notes
    cell are read as written (issue 37)."""
    ref = np.full(20, 12.0)
    root = _write_set(tmp_path / "set", {"one": (_stripe(), None, ref, "red")}, manifest=None)
    long_note = "x" * 200_000  # beyond the csv module's default field limit (131,072)
    (root / "manifest.csv").write_bytes(
        ("\ufeffname,has_background,laser_colour,notes\r\n"
         f'one,0,red,"first\u2028second\u0085third {long_note}"\r\n').encode("utf-8"))
    (root / "one_ref.csv").write_bytes(("\ufeffrow,col\r\n" + "".join(f"{i},12\r\n" for i in range(20))).encode())
    images, problems = real.validate_dataset(root)
    assert problems == [] and [i.name for i in images] == ["one"]
    assert images[0].load()[3][5] == 12.0


def test_a_field_beyond_the_bound_is_one_line(tmp_path):
    from bench.store.textfiles import MAX_CSV_FIELD

    root = _write_set(tmp_path / "set", {"one": (_stripe(), None, np.full(20, 12.0), "red")})
    (root / "manifest.csv").write_text(f'name,has_background,laser_colour,notes\none,0,red,"{"x" * (MAX_CSV_FIELD + 1)}"\n')
    images, problems = real.validate_dataset(root)
    assert images == [] and len(problems) == 1
    assert problems[0].startswith("manifest.csv: not a readable CSV table (a field is longer than")


def test_a_nan_float_tiff_is_one_line_and_pillow_size_warnings_never_leak(tmp_path, monkeypatch):
    """Issue 37 item 7: a NaN float TIFF and a PNG over Pillow's decompression-bomb size printed warnings."""
    import warnings

    from PIL import Image

    a = np.full((20, 30), 10.0, np.float32)
    a[3, 4] = np.nan
    tifffile.imwrite(tmp_path / "nan.tif", a)
    with pytest.raises(real.ImageError, match=r"nan.tif': 1 NaN or infinite pixel value\(s\); a frame must be finite"):
        real.read_image(tmp_path / "nan.tif")
    iio.imwrite(tmp_path / "big.png", _stripe())
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 400)  # Pillow warns (a "decompression bomb") above 400 px
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert real.read_image(tmp_path / "big.png").shape == (20, 30)
    monkeypatch.setattr(real, "MAX_PIXELS", 500)  # our own bound: one line
    with pytest.raises(real.ImageError, match=r"30x20 pixels, more than the 500 read"):
        real.read_image(tmp_path / "big.png")


@pytest.mark.parametrize("orientation, rotate_deg, says", [
    (1, 0, None), (3, 0, "--rotate 180"), (6, 0, "--rotate 270"), (8, 0, "--rotate 90"), (8, 90, None),
    (6, 90, "--rotate 270"), (2, 0, "mirrored")])
def test_the_orientation_note_says_which_turn_shows_a_file_as_its_exif_asks(tmp_path, orientation, rotate_deg, says):
    from PIL import Image

    exif = Image.Exif()
    exif[0x0112] = orientation
    Image.new("RGB", (8, 6)).save(tmp_path / "a.jpg", exif=exif)
    assert real.exif_orientation(tmp_path / "a.jpg") == orientation
    note = real.orientation_note(tmp_path / "a.jpg", rotate_deg)
    if says is None:
        assert note is None
    else:
        assert note.startswith(f"a.jpg: EXIF orientation {orientation} (shown") and says in note and "\n" not in note
    assert real.read_image(tmp_path / "a.jpg").shape == (6, 8, 3)  # read as stored, whatever the tag


def test_a_file_without_exif_or_not_an_image_has_no_orientation(tmp_path):
    iio.imwrite(tmp_path / "a.png", np.zeros((4, 5), np.uint8))
    (tmp_path / "b.jpg").write_bytes(b"not a jpeg")
    assert real.exif_orientation(tmp_path / "a.png") == 1 and real.exif_orientation(tmp_path / "b.jpg") == 1
    assert real.orientation_note(tmp_path / "a.png") is None


def test_whether_a_reference_gives_row_states_is_read_from_its_header(tmp_path):
    (tmp_path / "a_ref.csv").write_text("row,col,state\n0,1.5,stripe\n")
    (tmp_path / "b_ref.csv").write_text("\ufeffrow, col\r\n0,1.5\r\n")  # a byte-order mark, spaces, CRLF
    (tmp_path / "c_ref.csv").write_text("r,c\n0,1.5\n")
    assert real.reference_gives_states(tmp_path / "a_ref.csv") is True
    assert real.reference_gives_states(tmp_path / "b_ref.csv") is False
    with pytest.raises(real.DatasetError, match=r"c_ref.csv: header must be 'row,col' or 'row,col,state', got 'r,c'"):
        real.reference_gives_states(tmp_path / "c_ref.csv")
    with pytest.raises(real.DatasetError, match="d_ref.csv: cannot read reference"):
        real.reference_gives_states(tmp_path / "d_ref.csv")
