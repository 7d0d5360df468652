"""floor="auto" and named floors: which world geom becomes the sand surface, and the warnings for the rigid
collision floors the robot can still stand on (mjrft.floor._find_floor)."""

from __future__ import annotations

import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft import SandContactWarning

ROBOT = """<body name="robot" pos="0 0 {z}"><freejoint/>
      <geom name="torso" type="box" size="0.1 0.1 0.05" mass="1"/>
    </body>"""


def model(world: str, z: float = 0.1, asset: str = "") -> mujoco.MjModel:
    """A 0.2 x 0.2 x 0.1 m box robot at height ``z`` over the world geoms ``world``."""
    return mujoco.MjModel.from_xml_string(f"<mujoco>{asset}<worldbody>{world}{ROBOT.format(z=z)}</worldbody></mujoco>")


def gid(m, name: str) -> int:
    return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, name)


def terrain(m, floor="auto"):
    """The terrain, and the SandContactWarnings its constructor gave."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t = mjrft.GranularTerrain(m, floor=floor, resolution=0.05)
    return t, [str(w.message) for w in caught if issubclass(w.category, SandContactWarning)]


PLANE = '<geom name="floor" type="plane" size="2 2 0.1"/>'
WALL = '<geom name="wall" type="plane" size="1 1 0.1" pos="2 0 0.5" zaxis="-1 0 1"/>'  # tilted, as dm_control's


def test_the_surface_is_the_chosen_floors_own_top():
    # a 0.3 m box beside the robot, after the plane: the plane is the floor and its top (0) the surface
    m = model(PLANE + '<geom name="box" type="box" size="0.2 0.2 0.15" pos="1 0 0.15"/>')
    t, notes = terrain(m)
    assert t.floor == gid(m, "floor") and t.surface == 0.0 and not notes
    assert m.geom_contype[gid(m, "box")] == 1  # the box beside the robot keeps its contacts
    # the same box under the robot is what it stands on: its own top is the surface, wherever it is listed
    for world in ('<geom name="box" type="box" size="0.5 0.5 0.15" pos="0 0 0.15"/>' + PLANE,
                  PLANE + '<geom name="box" type="box" size="0.5 0.5 0.15" pos="0 0 0.15"/>'):
        m = model(world, z=0.4)
        t, notes = terrain(m)
        assert t.floor == gid(m, "box") and t.surface == pytest.approx(0.3)


def test_a_tilted_plane_last_is_never_chosen_and_does_not_crash():
    m = model(PLANE + WALL)
    t, notes = terrain(m)
    assert t.floor == gid(m, "floor") and t.surface == 0.0 and not notes
    assert m.geom_contype[gid(m, "wall")] == 1
    with pytest.raises(ValueError, match="floor geom 'wall' cannot be the sand surface: it is tilted"):
        mjrft.GranularTerrain(model(PLANE + WALL), floor="wall")
    # a box turned off the horizontal, last: not a floor either
    tilted = '<geom name="ramp" type="box" size="1 1 0.1" pos="0 0 -0.1" euler="0 20 0"/>'
    m = model(PLANE + tilted)
    assert terrain(m)[0].floor == gid(m, "floor")


# dm_control's quadruped.xml: a plane, four tilted walls, and a flat height field 1 cm below the plane
HFIELD_ASSET = '<asset><hfield name="hf" nrow="3" ncol="3" size="3 3 0.5 0.1"/></asset>'
HFIELD = '<geom name="terrain" type="hfield" hfield="hf" pos="0 0 -0.01"/>'


def test_auto_takes_the_highest_floor_and_warns_about_a_rigid_one_within_reach():
    m = model(PLANE + WALL + HFIELD, asset=HFIELD_ASSET)
    t, notes = terrain(m)
    # the plane the robot stands on becomes the sand (its contacts removed) ...
    assert t.floor == gid(m, "floor") and t.surface == 0.0
    assert (m.geom_contype[gid(m, "floor")], m.geom_conaffinity[gid(m, "floor")]) == (0, 0)
    # ... and the height field 1 cm under it, which the robot meets after sinking 1 cm, is named
    assert len(notes) == 1 and "'terrain' (hfield, top -0.01 m)" in notes[0] and "0.01 m below" in notes[0]
    assert "remove its contacts" in notes[0] and f"model.geom_contype[{gid(m, 'terrain')}]" in notes[0]
    assert m.geom_contype[gid(m, "terrain")] == 1
    # control: a rigid floor deeper than the robot's size (0.2 m) is the bed's bottom, not warned about
    deep = HFIELD.replace("-0.01", "-0.5")
    m = model(PLANE + WALL + deep, asset=HFIELD_ASSET)
    t, notes = terrain(m)
    assert t.floor == gid(m, "floor") and not notes


def test_a_named_floor_below_another_collision_floor_warns_naming_it():
    m = model(PLANE + WALL + HFIELD, asset=HFIELD_ASSET)
    with pytest.warns(SandContactWarning, match=r"geom 'floor' \(plane, top 0 m\) is a collision floor under the "
                                                r"robot at or above the sand surface \(-0.01 m, the top of 'terrain'\)"
                                                r".*floor='floor'"):
        t = mjrft.GranularTerrain(m, floor="terrain", resolution=0.05)
    assert t.floor == gid(m, "terrain") and m.geom_contype[gid(m, "floor")] == 1


def test_floors_that_do_not_collide_with_the_robot_are_neither_chosen_nor_warned_about():
    # a plane above the floor whose collision bits miss the robot's (contype 2, conaffinity 2 against 1, 1)
    other = '<geom name="other" type="plane" size="2 2 0.1" pos="0 0 0.02" contype="2" conaffinity="2"/>'
    m = model(PLANE + other)
    t, notes = terrain(m)
    assert t.floor == gid(m, "floor") and not notes
    # control: an explicit <pair> joins it to the robot, so the robot stands on it: it is the floor now
    pair = '<contact><pair geom1="other" geom2="torso"/></contact>'
    m = mujoco.MjModel.from_xml_string(f"<mujoco><worldbody>{PLANE}{other}{ROBOT.format(z=0.1)}</worldbody>"
                                       f"{pair}</mujoco>")
    t, notes = terrain(m)
    assert t.floor == gid(m, "other") and t.surface == pytest.approx(0.02)
    assert len(notes) == 1 and "'floor' (plane, top 0 m)" in notes[0] and "0.02 m below" in notes[0]


def test_the_robot_no_longer_stands_on_the_rigid_plane():
    """quadruped.xml's layout: with the plane as the sand the robot is carried by the grains (the hfield 1 cm below
    is out of reach for this light box in poppy seeds, as its sinkage shows)."""
    m = model(PLANE + WALL + HFIELD.replace("-0.01", "-0.05"), z=0.06, asset=HFIELD_ASSET)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", resolution=0.02)
    d = mujoco.MjData(m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t.step(d, 600)
    weight = float(m.body_subtreemass[0]) * 9.81
    assert d.ncon == 0 and t.wrench[:, 2].sum() == pytest.approx(weight, rel=0.05)
    assert 0 < t.sinkage().max() < 0.05


TARGET = '<geom name="target" type="cylinder" size="0.1 0.002" pos="{x} 0 {z}"/>'  # dm_control dog.xml's, flat


def test_a_rigid_world_geom_that_is_not_a_floor_under_the_robot_is_named():
    """dm_control's dog scene has a flat collision cylinder at the origin: under floor='auto' the robot rests on it
    and not on the sand. Any rigid geom of the world under the robot (its bounding box within the selected geoms'
    in x, y) that reaches the sand is named; controls: the same cylinder beside the robot, or deeper than the
    robot's size, is not."""
    m = model(PLANE + TARGET.format(x=0, z=0.002))
    t, notes = terrain(m)
    assert t.floor == gid(m, "floor") and m.geom_contype[gid(m, "target")] == 1
    assert len(notes) == 1 and "geom 'target' (cylinder, top 0.004 m) is a rigid collision geom of the world under " \
        "the robot at or above the sand surface (0 m, the top of 'floor')" in notes[0]
    assert f"model.geom_contype[{gid(m, 'target')}] = model.geom_conaffinity[{gid(m, 'target')}] = 0" in notes[0]
    assert not terrain(model(PLANE + TARGET.format(x=1, z=0.002)))[1]
    assert not terrain(model(PLANE + TARGET.format(x=0, z=-0.5)))[1]
    below = terrain(model(PLANE + TARGET.format(x=0, z=-0.05)))[1]
    assert len(below) == 1 and "0.048 m below the sand surface" in below[0]


def test_a_surface_given_as_a_height_names_a_collision_floor_left_at_it():
    """floor=None (the default: the surface is a height, here 0, and the model's floors keep their contacts): a
    collision plane at the surface carries the robot and the sand gives no force, so it is named with the cure.
    Controls: a plane below the surface (the bed's rigid bottom by design) or one whose collision bits miss the
    robot's is not named."""
    m = model(PLANE)
    t, notes = terrain(m, floor=None)
    assert t.floor is None and m.geom_contype[gid(m, "floor")] == 1
    assert len(notes) == 1 and "geom 'floor' (plane, top 0 m) is a collision floor under the robot at or above the " \
        "sand surface (0 m, the surface height)" in notes[0] and "floor='floor', or floor='auto'" in notes[0]
    assert not terrain(model(PLANE.replace('size=', 'pos="0 0 -0.05" size=')), floor=None)[1]
    assert not terrain(model(PLANE.replace('size=', 'contype="2" conaffinity="2" size=')), floor=None)[1]
    assert not terrain(model(TARGET.format(x=0, z=-0.05)), floor=None)[1]  # nor any other rigid geom below it
    above = terrain(model(TARGET.format(x=0, z=0.002)), floor=None)[1]  # a geom reaching above it is
    assert len(above) == 1 and "'target' (cylinder, top 0.004 m) is a rigid collision geom" in above[0]


def test_geoms_that_meet_the_floor_only_through_pairs_are_selected_and_carry_the_robot():
    """Feet with contype = conaffinity = 0 that touch the floor through explicit <pair>s (MuJoCo Playground's Apollo)
    are collision geoms: selected by default, they stand in the sand (the pairs with the floor taken out of reach).
    Control: without the pairs they are visual-only and left out, and the torso alone is selected."""
    feet = ('<geom name="foot_a" type="box" pos="-0.1 0 -0.08" size="0.03 0.06 0.01" contype="0" conaffinity="0"/>'
            '<geom name="foot_b" type="box" pos="0.1 0 -0.08" size="0.03 0.06 0.01" contype="0" conaffinity="0"/>')
    pairs = '<contact><pair geom1="foot_a" geom2="floor"/><pair geom1="foot_b" geom2="floor"/></contact>'
    robot = ROBOT.format(z=0.1).replace("</body>", feet + "</body>")
    m = mujoco.MjModel.from_xml_string(f"<mujoco><worldbody>{PLANE}{robot}</worldbody>{pairs}</mujoco>")
    t, notes = terrain(m)
    assert sorted(m.geom(g).name for g in t.geom_ids) == ["foot_a", "foot_b", "torso"] and not notes
    d = mujoco.MjData(m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t.step(d, 800)
    soles = d.geom_xpos[[gid(m, "foot_a"), gid(m, "foot_b")], 2] - 0.01
    weight = float(m.body_subtreemass[0]) * 9.81
    assert d.ncon == 0 and t.wrench[:, 2].sum() == pytest.approx(weight, rel=0.05)
    assert np.all(soles < 0.0) and d.qpos[2] - 0.05 > 0.0  # the soles in the sand carry it; the torso stays above
    m = mujoco.MjModel.from_xml_string(f"<mujoco><worldbody>{PLANE}{robot}</worldbody></mujoco>")
    assert [m.geom(g).name for g in terrain(m)[0].geom_ids] == ["torso"]


BRICK = """<mujoco><worldbody><geom name="plane" type="plane" size="5 5 0.1"/>
<geom name="brick" type="box" size="0.05 0.03 0.05" pos="0 0 0.05"/>
<body name="robot" pos="0 0 0.2"><freejoint/><geom name="trunk" type="box" size="0.2 0.1 0.03" mass="5"/>
  <geom name="fl" type="sphere" size="0.02" pos="0.18 0.1 -0.17" mass="0.1"/>
  <geom name="fr" type="sphere" size="0.02" pos="0.18 -0.1 -0.17" mass="0.1"/>
  <geom name="hl" type="sphere" size="0.02" pos="-0.18 0.1 -0.17" mass="0.1"/>
  <geom name="hr" type="sphere" size="0.02" pos="-0.18 -0.1 -0.17" mass="0.1"/></body></worldbody></mujoco>"""


def test_an_auto_floor_smaller_than_the_robot_is_named_and_the_plane_below_offered():
    m = mujoco.MjModel.from_xml_string(BRICK)  # a 10 cm brick under the belly of a robot standing on a plane
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", resolution=0.01)
    notes = [str(w.message) for w in caught if issubclass(w.category, mjrft.SandContactWarning)]
    assert t.floor == m.geom("brick").id  # the highest floor under the robot, as documented
    assert any("floor='auto' chose geom 'brick'" in n and "smaller than the robot's footprint" in n for n in notes)
    plane = [n for n in notes if "'plane'" in n]
    assert plane and "name it as the floor (floor='plane')" in plane[0] and "remove its contacts" not in plane[0]
    # control: the plane named as the floor gives no footprint note
    m = mujoco.MjModel.from_xml_string(BRICK)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mjrft.GranularTerrain(m, "poppy_cp", floor="plane", resolution=0.01)
    assert not any("footprint" in str(w.message) for w in caught)
