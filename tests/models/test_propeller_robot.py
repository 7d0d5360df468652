"""The SGRFT propeller-leg: its rig shape (models.rigs.propeller_geometry) and the propeller-leg robot."""

import math
import warnings

import mujoco
import numpy as np
import pytest

from mjrft import GranularTerrain
from mjrft.models.propeller_robot import CLEARANCE, default_mass, propeller_robot_model, propeller_robot_xml
from mjrft.models.rigs import PROPELLER_RADIUS, leg_geometry, leg_rig_model, propeller_geometry


def test_propeller_geometry():
    g = propeller_geometry(0.11, 0.5, 3, 0.025, 0.002)
    assert g["blades"] == 3 and g["blade_angles"] == pytest.approx([0, 2 * math.pi / 3, 4 * math.pi / 3])
    r = np.hypot(g["vertices"][:, 0], g["vertices"][:, 2])
    assert r.max() == pytest.approx(0.11, abs=2e-3)  # tips on the 110 mm circle (thickness aside)
    assert g["curvature"] == pytest.approx(2 * math.sin(0.25) / 0.11)
    # a blade hanging straight down (leg angle 0) bows toward -x: convex side leading (C-leg convention)
    one = g["mesh"][0]
    assert one[:, 0].min() < -0.005 and one[:, 0].max() < 0.003
    # three blades, 120 deg apart: the tips of blades 2 and 3 point back-up and front-up
    tips = g["vertices"].reshape(3, -1, 3)
    lowest = [t[np.argmin(t[:, 2])] for t in tips]
    assert lowest[0][2] == pytest.approx(-0.11, abs=2e-3)
    assert lowest[1][2] > -0.06 and lowest[2][2] > -0.06


@pytest.mark.parametrize("kw, word", [({"arc": 0.0}, "arc"), ({"arc": 4.0}, "arc"), ({"arc": math.nan}, "arc"),
                                      ({"blades": 0}, "blades"), ({"blades": 1.5}, "blades"),
                                      ({"radius": -0.1}, "radius")])
def test_propeller_bad_input(kw, word):
    with pytest.raises(ValueError, match=word):
        propeller_geometry(**kw)


def test_propeller_shape_options():
    with pytest.raises(ValueError, match="arc"):
        leg_geometry("propeller", curvature=5.0)
    with pytest.raises(ValueError, match="propeller"):
        leg_geometry("c", arc=0.5)
    m = leg_rig_model("propeller", chord=0.11, arc=math.pi / 2, blades=3)
    assert sum(m.geom_bodyid[g] == m.body("leg").id for g in range(m.ngeom)) == 3


def test_robot_model():
    m = propeller_robot_model()
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    assert m.body_subtreemass[m.body("body").id] == pytest.approx(default_mass())
    assert default_mass() == pytest.approx(3.6)
    assert m.nu == 2 and m.actuator("hub_l").trntype == mujoco.mjtTrn.mjTRN_JOINT
    # qpos0: a blade of each propeller and the wheels' lowest points CLEARANCE above the surface
    lows = {}
    for name in ("prop_l", "wheel_l"):
        b = m.body(name).id
        zs = [d.geom_xpos[g][2] - (m.geom_rbound[g] if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_CYLINDER else 0)
              for g in range(m.ngeom) if m.geom_bodyid[g] == b]
        lows[name] = min(zs)
    assert lows["wheel_l"] <= CLEARANCE + 1e-9
    assert m.body_pos[m.body("body").id][2] == pytest.approx(PROPELLER_RADIUS + CLEARANCE)
    with pytest.raises(ValueError, match="mass"):
        propeller_robot_xml(mass=0.2)
    with pytest.raises(TypeError, match="bogus"):
        propeller_robot_xml(bogus=1)


@pytest.mark.parametrize("rpm", [0.0, 60.0])
def test_robot_runs_forward_on_sand(rpm):
    m = propeller_robot_model()
    d = mujoco.MjData(m)
    terrain = GranularTerrain(m)
    assert set(terrain.body_ids) == {m.body(n).id for n in ("body", "prop_l", "prop_r", "wheel_l", "wheel_r")}
    d.ctrl[:] = rpm * 2 * math.pi / 60
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        terrain.step(d, 1500)
    assert np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel))
    assert d.qpos[2] > 0.0  # carried by the sand above the rigid bed bottom
    if rpm == 0:
        assert abs(d.qpos[0]) < 0.01 and abs(d.qvel[0]) < 0.01  # at rest it stays put
    else:
        assert d.qpos[0] > 0.1  # moves forward (+x)
        hub = d.qpos[m.jnt_qposadr[m.joint("hub_l").id]]
        assert hub / d.time == pytest.approx(rpm * 2 * math.pi / 60, rel=0.05)
