"""Fig. 7's data and the failure gallery: keys in one module, formats checked."""

import numpy as np

from bench.store.figdata import FigData, GalleryFrame, read_figdata, read_gallery, write_figdata, write_gallery
from bench.store.files import load_npz, save_npz


def _fig(H=6, W=8):
    img = np.arange(H * W, dtype=np.uint8).reshape(H, W)
    return FigData("cone-patchy", 1.25, img, img // 2, np.linspace(1, 5, H), {"dp4": np.full(H, 2.0), "t": np.zeros(H)})


def test_figure_data_round_trips(tmp_path):
    write_figdata(tmp_path / "f.npz", _fig())
    back, why = read_figdata(tmp_path / "f.npz")
    assert why is None and back.experiment == "cone-patchy" and back.mirror_angle_deg == 1.25
    assert sorted(back.columns) == ["dp4", "t"] and np.array_equal(back.background, _fig().background)


def test_figure_data_of_another_format_or_shape_is_refused(tmp_path):
    p = tmp_path / "f.npz"
    write_figdata(p, _fig())
    a = load_npz(p)
    save_npz(p, **{**a, "format": np.array(4)})
    assert read_figdata(p) == (None, "of format 4 (this stripebench reads format 1, 2, 3)")
    save_npz(p, **{**a, "cost_field": np.zeros((2, 2))})
    assert "cost_field of shape (2, 2)" in read_figdata(p)[1]
    save_npz(p, **{**a, "columns/t": np.zeros(5)})
    assert "columns of 't'" in read_figdata(p)[1]
    a.pop("format")  # format 1: the same arrays without a number, read as they are
    save_npz(p, **a)
    assert read_figdata(p)[0] is not None


def test_the_cost_field_round_trips_and_older_files_have_none(tmp_path):
    import dataclasses

    p = tmp_path / "f.npz"
    cost = np.linspace(0, 1, 48).reshape(6, 8)
    write_figdata(p, dataclasses.replace(_fig(), cost_field=cost))
    assert np.array_equal(read_figdata(p)[0].cost_field, cost)
    a = load_npz(p)
    a.pop("cost_field")
    save_npz(p, **{**a, "format": np.array(2)})  # a format-2 file: no cost field saved
    assert read_figdata(p)[0].cost_field is None


def test_the_gallery_round_trips_in_key_order(tmp_path):
    H = 4
    frames = [GalleryFrame("plane-absorbing", 1, np.ones((H, 3), np.uint8), np.arange(H, dtype=float),
                           {"b": np.zeros(H), "a": np.ones(H)}),
              GalleryFrame("cone-patchy", 12, np.zeros((H, 3), np.uint8), np.full(H, np.nan), {"b": np.zeros(H)})]
    write_gallery(tmp_path / "g.npz", frames)
    back, why = read_gallery(tmp_path / "g.npz")
    assert why is None and [g.key for g in back] == ["cone-patchy/12", "plane-absorbing/1"]
    assert list(back[1].columns) == ["b", "a"]  # the order written
    assert [str(k) for k in load_npz(tmp_path / "g.npz")["keys"]] == ["cone-patchy/12", "plane-absorbing/1"]


def test_a_gallery_with_a_bad_key_or_missing_frame_is_refused(tmp_path):
    p = tmp_path / "g.npz"
    save_npz(p, keys=np.array(["nokey"]))
    assert "not <experiment>/<frame>" in read_gallery(p)[1]
    save_npz(p, keys=np.array(["e/1"]))
    assert "lacks 'image'" in read_gallery(p)[1]
    save_npz(p, x=np.zeros(2))
    assert read_gallery(p) == (None, "no `keys` array")
