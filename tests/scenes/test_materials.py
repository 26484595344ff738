import numpy as np
import pytest

from scenes import materials as M


def test_every_material_has_a_bsdf():
    assert M.MATERIALS == ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed")
    types = {m: M.bsdf(m)["type"] for m in M.MATERIALS}
    assert types == {"matte": "diffuse", "absorbing": "diffuse", "glossy": "roughplastic",
                     "specular": "conductor", "patchy": "diffuse", "polished": "roughconductor",
                     "glazed": "roughplastic"}
    assert M.bsdf("absorbing")["reflectance"] == pytest.approx(0.05)
    assert M.bsdf("glossy")["distribution"] == "ggx"
    assert [m for m in M.MATERIALS if M.uses_delta_bsdf(m)] == ["specular"]


def test_unknown_material_lists_the_valid_ones():
    with pytest.raises(KeyError, match="matte, absorbing"):
        M.bsdf("velvet")


def test_patchy_texture_has_dark_horizontal_bands_and_patches():
    tex = M.patchy_texture(256)[..., 0]
    dark = tex < 0.1
    assert 0.2 < dark.mean() < 0.5
    full_rows = dark.all(axis=1)
    assert full_rows.sum() > 0.15 * 256  # bands cross the whole width
    # bands: several separate runs of fully dark rows
    assert np.sum(np.diff(full_rows.astype(int)) == 1) >= 3
    assert (dark & ~full_rows[:, None]).any()  # plus patches
    assert set(np.unique(tex)) == {np.float32(M.DARK_ALBEDO), np.float32(M.WHITE_ALBEDO)}


def test_shiny_materials_are_rough_versions_of_the_mirror():
    polished, specular, glazed = M.bsdf("polished"), M.bsdf("specular"), M.bsdf("glazed")
    assert (polished["eta"], polished["k"]) == (specular["eta"], specular["k"])  # same aluminium
    assert polished["distribution"] == glazed["distribution"] == "ggx"
    assert 0 < glazed["alpha"] < polished["alpha"] <= 0.1
    assert glazed["int_ior"] == pytest.approx(1.5) and glazed["diffuse_reflectance"] > M.bsdf("glossy")["diffuse_reflectance"]
    assert M.SHINY == ("specular", "polished", "glazed")


def test_integrator_per_material():
    kinds = {m: M.integrator_for(m) for m in M.MATERIALS}
    assert kinds == {"matte": "path", "absorbing": "path", "glossy": "path", "specular": "ptracer",
                     "patchy": "path", "polished": "split", "glazed": "split"}
    with pytest.raises(KeyError, match="unknown `material` 'velvet'"):
        M.integrator_for("velvet")


def test_docstring_examples_run():
    import doctest
    import importlib

    module = importlib.import_module("scenes.materials")
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0
