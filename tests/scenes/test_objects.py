import numpy as np
import pytest

from scenes import objects as O
from scenes.rig import Rig


@pytest.mark.parametrize("name", O.OBJECTS)
def test_objects_sit_20_to_60_cm_from_the_axis_centred_on_the_laser(name):
    rig = Rig()
    obj = O.build(name, rig.zeta_deg)
    v = obj.mesh.vertices_cm
    r = np.hypot(v[:, 0], v[:, 1])
    assert r.min() > 20.0 and r.max() < 60.0
    phi_lo, phi_hi = obj.phi_range_deg
    assert 0.5 * (phi_lo + phi_hi) == pytest.approx(-rig.zeta_deg, abs=1.5)  # angle 0 crosses the middle
    # backdrop behind the object, inside 20-60 cm over the swept azimuths
    b = obj.backdrop.vertices_cm
    n = obj.backdrop.face_normals()[0]
    assert np.allclose(n, -rig.laser_direction(0.0))  # faces the axis
    assert np.all((v - b[0]) @ n > 0)  # whole object in front of the wall
    dist = O.BACKDROP_DISTANCE_CM / np.cos(np.radians(np.array(obj.phi_range_deg) + rig.zeta_deg))
    assert np.all(dist < 60.0)


@pytest.mark.parametrize("name", O.OBJECTS)
def test_default_angles_sweep_past_both_edges(name):
    rig = Rig()
    obj = O.build(name, rig.zeta_deg)
    angles = obj.default_angles(rig.zeta_deg, 48)
    assert len(angles) == 48 and np.all(np.diff(angles) > 0)
    phi = rig.laser_phi_deg(angles)
    assert phi[0] < obj.phi_range_deg[0] and phi[-1] > obj.phi_range_deg[1]
    assert np.mean(angles) == pytest.approx(0.0, abs=0.75)


def test_object_heights_fit_the_field():
    rig = Rig()
    for name in ("cone", "hand", "sphere"):
        z = O.build(name, rig.zeta_deg).mesh.vertices_cm[:, 2]
        assert z.max() <= 4.5 and z.min() >= -4.5


def test_unknown_object_lists_valid_names():
    with pytest.raises(KeyError, match="cone, hand, plane, sphere"):
        O.build("teapot", 14.0)
