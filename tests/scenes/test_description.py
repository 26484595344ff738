import numpy as np
import pytest

from scenes import description as D, laser, materials, objects, shapes
from scenes.materials import MATERIALS
from scenes.rig import Rig

RIG = Rig().with_size(64, 60)
OBJ = objects.build("sphere", RIG.zeta_deg)
LASER = laser.profile(3.0, 90.0)


@pytest.mark.parametrize("material", MATERIALS)
def test_laser_scene_integrator_per_material(material):
    d = D.laser_scene(RIG, OBJ, material, LASER, 0.0, 8)
    expected = "ptracer" if material == "specular" else "path"
    passes = D.laser_passes(material)
    if material in ("skin", "marble", "wax"):
        assert d["integrator"] == {"type": "volpath", "max_depth": materials.MEDIUM_MAX_DEPTH}
        assert passes == (("volpath", materials.MEDIUM_MAX_DEPTH, "all"),)
    elif material in ("polished", "glazed"):
        assert d["integrator"] == {"type": "path", "max_depth": D.MAX_DEPTH}
        assert passes == (("path", D.MAX_DEPTH, "object"), ("ptracer", D.MAX_DEPTH, "other"))
    else:
        assert d["integrator"] == {"type": expected, "max_depth": D.MAX_DEPTH}
        assert passes == ((expected, D.MAX_DEPTH, "all"),)
    assert set(d) == {"type", "integrator", "sensor", "backdrop", "object", "laser"}
    assert d["object"]["mesh"] is OBJ.mesh and d["backdrop"]["mesh"] is OBJ.backdrop  # the sphere is closed


def test_ambient_scene_has_the_sky_and_no_laser():
    d = D.ambient_scene(RIG, OBJ, "matte", 0.0, 4)
    assert d["sky"] == {"type": "constant", "radiance": 1.0}
    assert "laser" not in d and d["integrator"]["type"] == "path"
    assert d["sensor"]["sampler"] == {"type": "multijitter", "sample_count": 4}


def test_sensor_and_projector_follow_the_rig():
    theta = 2.0
    s = D.sensor(RIG, theta, 16)
    assert np.array_equal(s["to_world"], RIG.camera_to_world_m(theta))
    assert s["film"]["width"] == 64 and s["film"]["height"] == 60 and s["film"]["rfilter"] == {"type": "box"}
    assert s["fov"] == pytest.approx(RIG.fov_x_deg) and s["fov_axis"] == "x"
    p = D.projector(RIG, theta, LASER, power_w=2.0)
    assert np.array_equal(p["to_world"], RIG.laser_to_world_m(theta))
    assert p["scale"] == pytest.approx(LASER.scale_for_power(2.0))
    up = D.pose_updates(RIG, theta)
    assert set(up) == {"sensor.to_world", "laser.to_world"}
    # the projector's optical axis (local +Z) is the laser direction, its up is +Z
    m = up["laser.to_world"]
    assert np.allclose(m[:3, 2], RIG.laser_direction(theta)) and np.allclose(m[:3, 1], [0, 0, 1])


def test_integrator_kind_is_checked():
    with pytest.raises(ValueError, match="`kind` must be 'path', 'ptracer' or 'volpath', got 'bdpt'"):
        D.integrator("bdpt")
    with pytest.raises(ValueError, match="`max_depth` must be an integer >= 1, got 0"):
        D.integrator("volpath", 0)
    assert D.integrator("volpath", 64) == {"type": "volpath", "max_depth": 64}
    assert D.integrator("path") == {"type": "path", "max_depth": D.MAX_DEPTH}


def test_background_and_support_shapes_follow_the_geometry():
    bare = objects.build("sphere", RIG.zeta_deg, "none", 55.0, "none")
    d = D.laser_scene(RIG, bare, "matte", LASER, 0.0, 8)
    assert "backdrop" not in d and "support" not in d and "object" in d
    full = objects.build("sphere", RIG.zeta_deg, "wall", 70.0, "table")
    for d in (D.laser_scene(RIG, full, "matte", LASER, 0.0, 8, background_albedo=0.2, support_albedo=0.7),
              D.ambient_scene(RIG, full, "matte", 0.0, 4, background_albedo=0.2, support_albedo=0.7)):
        assert d["backdrop"]["mesh"] is full.backdrop and d["support"]["mesh"] is full.support
        assert d["backdrop"]["bsdf"] == {"type": "diffuse", "reflectance": 0.2}
        assert d["support"]["bsdf"] == {"type": "diffuse", "reflectance": 0.7}
    assert D.laser_scene(RIG, OBJ, "matte", LASER, 0.0, 8)["backdrop"]["bsdf"]["reflectance"] == 0.5


def test_docstring_examples_run():
    import doctest
    import importlib

    module = importlib.import_module("scenes.description")
    with np.printoptions(legacy=False, sign="-", precision=8, suppress=False, floatmode="maxprec"):
        result = doctest.testmod(module, extraglobs={"np": np})
    assert result.attempted > 0 and result.failed == 0


def test_translucent_object_carries_its_medium_and_a_closed_mesh():
    plane = objects.build("plane", RIG.zeta_deg)
    d = D.laser_scene(RIG, plane, "skin", LASER, 0.0, 8)
    assert d["object"]["interior"] == materials.medium("skin") and d["object"]["bsdf"] == {"type": "null"}
    mesh = d["object"]["mesh"]
    assert not shapes.is_closed(plane.mesh) and shapes.is_closed(mesh)
    # the front face is the plane's own triangles: rays (and the truth) hit the same surface
    n = len(plane.mesh.vertices_cm)
    assert np.array_equal(mesh.vertices_cm[:n], plane.mesh.vertices_cm)
    assert np.array_equal(mesh.faces[:len(plane.mesh.faces)], plane.mesh.faces)
    assert D.ambient_scene(RIG, plane, "skin", 0.0, 4)["integrator"]["type"] == "volpath"
    assert "interior" not in D.laser_scene(RIG, plane, "matte", LASER, 0.0, 8)["object"]


@pytest.mark.parametrize("material", MATERIALS)
def test_ambient_integrator_per_material(material):
    d = D.ambient_scene(RIG, OBJ, material, 0.0, 4)["integrator"]
    if material in ("skin", "marble", "wax"):
        assert d == {"type": "volpath", "max_depth": materials.MEDIUM_MAX_DEPTH}
    else:  # shiny ones too: only their laser pass is split
        assert d == {"type": "path", "max_depth": D.MAX_DEPTH}


def test_translucent_object_keeps_the_wall_and_the_table():
    full = objects.build("plane", RIG.zeta_deg, "wall", 70.0, "table")
    d = D.laser_scene(RIG, full, "marble", LASER, 0.0, 8, background_albedo=0.2, support_albedo=0.7)
    assert d["backdrop"]["mesh"] is full.backdrop and d["support"]["mesh"] is full.support
    assert d["backdrop"]["bsdf"]["reflectance"] == 0.2 and d["support"]["bsdf"]["reflectance"] == 0.7
    assert d["object"]["interior"] == materials.medium("marble") and shapes.is_closed(d["object"]["mesh"])
    bare = objects.build("sphere", RIG.zeta_deg, "none", 55.0, "none")
    d = D.ambient_scene(RIG, bare, "wax", 0.0, 4)
    assert "backdrop" not in d and "support" not in d and d["object"]["interior"] == materials.medium("wax")
