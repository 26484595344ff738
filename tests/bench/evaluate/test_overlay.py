"""bench.evaluate.overlay: a line drawn over a photograph, found and undone."""

import numpy as np
import pytest

from bench.evaluate import overlay


def _stripe_with_a_line(seed: int = 3):
    """A curved red stripe (clipped core, unclipped flank) beside a texture of scattered dark and light pixels, and the
    same with a black line at opacity 0.5 drawn down it: on a pixel, between two (every third row), and two pixels
    apart where it is steep (rows 40-41). Returns (clean, drawn, covered: {(row, col): cover})."""
    rng = np.random.default_rng(seed)
    H, W = 80, 120
    cols = np.arange(W, dtype=float)
    centre = 60.0 + 10.0 * np.sin(np.arange(H) / 25.0)
    prof = np.minimum(1.0, 1.4 * np.exp(-0.5 * ((cols[None, :] - centre[:, None]) / 3.0) ** 2))
    clean = 60.0 + prof[..., None] * np.array([195.0, 120.0, 150.0]) + rng.normal(0.0, 2.0, (H, W, 3))
    clean[:, :30] = 120.0 + 80.0 * (rng.random((H, 30, 1)) > 0.5)  # a texture of dark and light pixels
    clean = np.clip(np.rint(clean), 0, 255).astype(np.uint8)
    drawn = clean.astype(float)
    covered = {}
    for r in range(5, 75):
        x = round(centre[r]) + (0.5 if r % 3 == 0 else 0.0)  # on a pixel, or between two
        if 40 <= r < 42:  # steep: two pixels apart, half each
            covered[(r, int(x) - 1)] = covered[(r, int(x) + 1)] = 0.5
        elif x % 1:
            covered[(r, int(x))] = covered[(r, int(x) + 1)] = 0.5
        else:
            covered[(r, int(x))] = 1.0
    for (r, c), cover in covered.items():
        drawn[r, c] *= 1.0 - 0.5 * cover
    return clean, np.clip(np.rint(drawn), 0, 255).astype(np.uint8), covered


def test_a_line_drawn_over_a_stripe_is_found_and_undone():
    """``line_pixels`` finds every pixel the line covers, with its share, and not the texture's scattered dips;
    ``undo_line`` brings each back within 1 DN (the rounding of the drawn frame, doubled) and changes no other."""
    clean, drawn, covered = _stripe_with_a_line()
    found = overlay.line_pixels(drawn)
    assert {(r, c): cover for r, c, cover in found} == covered
    back = overlay.undo_line(drawn, found)
    diff = np.abs(back.astype(int) - clean.astype(int))
    mask = np.zeros(clean.shape[:2], bool)
    mask[tuple(np.array(list(covered)).T)] = True
    assert diff[mask].max() <= 1 and diff[~mask].max() == 0
    assert len({r for r, *_ in overlay.line_pixels(clean)}) < 10  # no line: at most a few texture dips


def test_a_photograph_is_named_as_drawn_over_where_the_line_runs_through_a_quarter_of_its_rows():
    """``drawn_over``: the line's rows (``line_rows``) at least ``DRAWN_SHARE`` of the photograph's; a clean stripe, a
    grey frame and a line over a tenth of the rows are not."""
    clean, drawn, covered = _stripe_with_a_line()
    rows = len({r for r, _ in covered})
    assert rows == 70 and 0.9 * rows <= overlay.line_rows(drawn) <= rows  # its founding dips: not the steep rows
    assert overlay.drawn_over(drawn) and not overlay.drawn_over(clean)
    short = clean.copy()
    short[:8] = drawn[:8]  # the line in rows 5-7 only
    assert overlay.line_rows(short) <= 8 and not overlay.drawn_over(short)
    assert not overlay.drawn_over(drawn[..., 0])  # grey: every dip is even in its one channel


def test_the_overlay_functions_name_a_bad_argument_in_one_line():
    _, drawn, _ = _stripe_with_a_line()
    with pytest.raises(ValueError, match="`image` must be a colour photograph"):
        overlay.line_pixels(drawn[..., 0])
    with pytest.raises(ValueError, match="`alpha` must lie between 0 and 1, got 1.5"):
        overlay.line_rows(drawn, alpha=1.5)
    with pytest.raises(ValueError, match="`image` must hold integer DN"):
        overlay.undo_line(drawn.astype(float), [])
