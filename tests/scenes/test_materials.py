import numpy as np
import pytest

from scenes import materials as M


def test_every_material_has_a_bsdf():
    assert M.MATERIALS == ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed",
                           "skin", "marble", "wax")
    types = {m: M.bsdf(m)["type"] for m in M.MATERIALS}
    assert types == {"matte": "diffuse", "absorbing": "diffuse", "glossy": "roughplastic",
                     "specular": "conductor", "patchy": "diffuse", "polished": "roughconductor",
                     "glazed": "roughplastic", "skin": "null", "marble": "null", "wax": "null"}
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
                     "patchy": "path", "polished": "split", "glazed": "split",
                     "skin": "volpath", "marble": "volpath", "wax": "volpath"}
    assert kinds == {m: M.integrator_for(m, "laser") for m in M.MATERIALS}
    ambient = {m: M.integrator_for(m, "ambient") for m in M.MATERIALS}
    assert ambient == {m: "volpath" if m in ("skin", "marble", "wax") else "path" for m in M.MATERIALS}

# -- translucent materials -----------------------------------------------------------------------------

def test_translucent_coefficients_are_jensen_2001_table_1_red_channel():
    # Jensen, Marschner, Levoy, Hanrahan (2001), Table 1, R channel, mm^-1:
    # Skin1 sigma_s' = 0.74, sigma_a = 0.032; Marble sigma_s' = 2.19, sigma_a = 0.0021
    assert M.TRANSLUCENT["skin"].sigma_s_reduced_per_mm == 0.74
    assert M.TRANSLUCENT["skin"].sigma_a_per_mm == 0.032
    assert M.TRANSLUCENT["marble"].sigma_s_reduced_per_mm == 2.19
    assert M.TRANSLUCENT["marble"].sigma_a_per_mm == 0.0021
    assert "Table 1" in M.TRANSLUCENT["skin"].source and "Skin1" in M.TRANSLUCENT["skin"].source
    assert "assumed" in M.TRANSLUCENT["wax"].source  # no published source: said so


@pytest.mark.parametrize("material", ["skin", "marble", "wax"])
def test_medium_is_in_metres_and_keeps_the_reduced_coefficients(material):
    t = M.TRANSLUCENT[material]
    m = M.medium(material)
    assert m["type"] == "homogeneous" and m["phase"] == {"type": "hg", "g": M.PHASE_G}
    sigma_s_per_m = m["sigma_t"] * m["albedo"]
    sigma_a_per_m = m["sigma_t"] * (1.0 - m["albedo"])
    # scene units are metres: mm^-1 x 1000; with g the medium's sigma_s (1 - g) is the published sigma_s'
    assert sigma_s_per_m * (1.0 - M.PHASE_G) == pytest.approx(1000.0 * t.sigma_s_reduced_per_mm)
    assert sigma_a_per_m == pytest.approx(1000.0 * t.sigma_a_per_mm)
    assert M.bsdf(material) == {"type": "null"}
    assert M.is_translucent(material) and not M.uses_delta_bsdf(material)
    assert M.integrator_for(material, "laser") == M.integrator_for(material, "ambient") == "volpath"
    assert material not in M.SHINY


def test_opaque_materials_have_no_medium_and_keep_their_integrators():
    for m in ("matte", "absorbing", "glossy", "specular", "patchy", "polished", "glazed"):
        assert M.medium(m) is None and not M.is_translucent(m)
        assert M.integrator_for(m, "ambient") == "path"


def test_integrator_for_checks_its_arguments():
    with pytest.raises(ValueError, match="`light` must be 'laser' or 'ambient', got 'sun'"):
        M.integrator_for("skin", "sun")
    with pytest.raises(KeyError, match="unknown `material` 'velvet'"):
        M.integrator_for("velvet")


def test_diffusion_lengths_order_the_materials():
    # skin absorbs most at 650 nm: the shortest reach; marble and wax glow over centimetres
    d = {k: v.diffusion_length_mm for k, v in M.TRANSLUCENT.items()}
    assert d["skin"] == pytest.approx(1.0 / np.sqrt(3 * 0.032 * (0.74 + 0.032)))
    assert d["skin"] < d["marble"] and d["skin"] < d["wax"]


def test_docstring_examples_run():
    import doctest
    import importlib

    module = importlib.import_module("scenes.materials")
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0


def test_textured_albedos_and_the_polished_table():
    tex = {"type": "bitmap"}
    assert M.with_albedo("matte", tex) == {"type": "diffuse", "reflectance": tex}
    assert M.with_albedo("glazed", tex)["diffuse_reflectance"] is tex and M.with_albedo("glazed", tex)["alpha"] == 0.02
    with pytest.raises(ValueError, match="an `object_texture` needs one of the materials 'matte', 'glossy', 'glazed'"):
        M.with_albedo("polished", tex)
    assert M.backdrop_bsdf(0.3) == {"type": "diffuse", "reflectance": 0.3}
    assert M.backdrop_bsdf(0.3, tex)["reflectance"] is tex
    coat = M.support_bsdf(0.4, None, "polished")
    assert coat["type"] == "roughplastic" and coat["diffuse_reflectance"] == 0.4 and coat["alpha"] == M.POLISHED_FLOOR_ALPHA
    with pytest.raises(ValueError, match="`support_finish` must be one of 'matte', 'polished', got 'wet'"):
        M.support_bsdf(0.4, None, "wet")
