import numpy as np
import pytest

from scenes import radiometry, textures as T

NAMES = T.TEXTURES[1:]


@pytest.mark.parametrize("name", NAMES)
def test_tiles_are_seeded_periodic_reflectances(name):
    t = T.tile(name, seed=3)
    n = T.TILE_TEXELS[name]
    assert t.shape == (n, n, 3) and t.dtype == np.float32
    assert 0.0 <= t.min() and t.max() <= 1.0 and t.std() > 0.001
    assert np.array_equal(t, T.tile(name, seed=3))  # a pure function of its seed
    assert not np.array_equal(t, T.tile(name, seed=4)) or name == "checker"  # the checker has no randomness
    assert not np.array_equal(T.tile(name, 0, "backdrop"), T.tile(name, 0, "support")) or name == "checker"
    # seamless: the step across the wrap (last row -> first row, last column -> first) is no larger
    # than the largest step between neighbouring rows (columns) inside the tile
    for axis in (0, 1):
        inner = np.abs(np.diff(t, axis=axis)).mean(axis=tuple(a for a in (0, 1, 2) if a != axis))
        wrap = np.abs(np.take(t, 0, axis) - np.take(t, -1, axis)).mean()
        assert wrap <= inner.max() + 1e-6, (axis, wrap, inner.max())


def test_checker_and_charuco_are_black_and_white_squares_of_the_scale():
    c = T.tile("checker")[..., 0]
    n = c.shape[0]
    assert np.allclose(np.unique(c), [T.BLACK_INK, T.WHITE_PAPER])
    assert c[0, 0] != c[0, n // 2] and c[0, 0] == c[n // 2, n // 2]  # two squares per tile side
    assert T.tile_cm("checker", 1.5) == 3.0
    ch = T.tile("charuco")[..., 0]
    q = ch.shape[0] // 4
    black = ch[q // 2, q // 2] == np.float32(T.BLACK_INK)
    # a white square holds a black-bordered marker (its border ring is black, its corner white)
    r0 = q if black else 0
    sq = ch[r0:r0 + q, 0:q]
    assert sq[0, 0] == np.float32(T.WHITE_PAPER) and (sq == np.float32(T.BLACK_INK)).mean() > 0.2


def test_paper_is_plain_white_and_print_has_colour():
    p = T.tile("paper")
    assert abs(float(p.mean()) - T.WHITE_PAPER) < 0.01 and float(p.std()) < 0.02
    pr = T.tile("print")
    chroma = pr.max(axis=-1) - pr.min(axis=-1)
    assert (chroma > 0.3).mean() > 0.01 and (pr.max(axis=-1) < 0.1).mean() > 0.005  # patches and ink


def test_band_weights_of_the_basis():
    B = T.basis_spectra()
    assert np.allclose(B.sum(axis=1), 1.0, atol=1e-4)  # grey is spectrally flat
    flat = np.ones_like(radiometry.WAVELENGTHS_NM)
    assert np.allclose(T.band_weights(flat).sum(), 1.0, atol=1e-4)
    red, blue = T.band_weights(wavelength_nm=650.0), T.band_weights(wavelength_nm=450.0)
    assert red[0] > 0.8 and blue[2] > 0.8
    a = T.albedo_map(np.full((2, 2, 3), 0.5, np.float32), red)
    assert a.shape == (2, 2, 1) and np.allclose(a, 0.5, atol=1e-4)
    with pytest.raises(ValueError, match="exactly one"):
        T.band_weights()
    with pytest.raises(ValueError, match="`weighting` must be finite"):
        T.band_weights(-flat)


def test_bitmap_maps_cm_to_tiles():
    d = T.bitmap(np.zeros((4, 4, 1), np.float32), np.diag([90.0, 40.0, 1.0]), 4.0)
    assert d["type"] == "bitmap" and d["raw"] is True and d["wrap_mode"] == "repeat"
    assert np.allclose(d["to_uv"][:2, :2], np.diag([22.5, 10.0])) and d["to_uv"].shape == (4, 4)


@pytest.mark.parametrize("bad,match", [(("none", 0, "backdrop"), "`texture` must be one of"),
                                       (("wood", -1, "backdrop"), "`seed` must be an integer >= 0, got -1"),
                                       (("wood", 0, "ceiling"), "`surface` must be one of")])
def test_bad_arguments(bad, match):
    with pytest.raises(ValueError, match=match):
        T.tile(*bad)
