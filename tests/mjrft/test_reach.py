"""Whether a terrain's selected geoms can ever meet the sand (mjrft/reach.py): the core terrain says so at
construction, as GranularWrapper does for gymnasium's robots (tests/envs/test_wrapper.py)."""

from __future__ import annotations

import warnings

import mujoco

import mjrft

ARM = """<mujoco><worldbody>
<body name="base" pos="0 0 0.5"><joint name="shoulder" type="hinge" axis="0 1 0" range="-30 30" limited="true"/>
  <geom name="upper" type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" mass="0.5"/>
  <body name="fore" pos="0.2 0 0"><joint name="elbow" type="hinge" axis="0 1 0" range="-30 30" limited="true"/>
    <geom name="lower" type="capsule" fromto="0 0 0 0.15 0 0" size="0.015" mass="0.3"/></body></body>
</worldbody><actuator><motor joint="shoulder"/><motor joint="elbow"/></actuator></mujoco>"""
BOX = """<mujoco><worldbody><body name="box" pos="0 0 0.5"><freejoint/>
<geom type="box" size=".05 .05 .05" mass="1"/></body></worldbody></mujoco>"""


def sand_notes(xml: str) -> list[str]:
    m = mujoco.MjModel.from_xml_string(xml)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mjrft.GranularTerrain(m, "poppy_cp", resolution=0.01)
    return [str(w.message) for w in caught if issubclass(w.category, mjrft.SandContactWarning)]


def test_a_fixed_arm_above_the_sand_is_named_at_construction():
    notes = sand_notes(ARM)  # 0.5 m up, its joints turning +-30 deg: the forearm's tip stays above 0.2 m
    assert len(notes) == 1 and "never reach the sand surface at 0 m" in notes[0]
    assert "'lower' (body 'fore'" in notes[0]


def test_control_a_free_body_above_the_sand_can_fall_onto_it():
    assert not sand_notes(BOX)


def test_a_body_with_visual_geoms_only_that_can_fall_is_named():
    xml = BOX.replace("</worldbody>", '<body name="ghost" pos="0.3 0 0.2"><freejoint/><geom type="sphere" '
                      'size="0.02" mass="0.1" contype="0" conaffinity="0"/></body></worldbody>')
    notes = sand_notes(xml)
    assert len(notes) == 1 and "bodies 'ghost' have no collision geom" in notes[0] and "sink" in notes[0]
    # control: welded to the world it cannot fall, and selected it feels the grains
    welded = xml.replace('<body name="ghost" pos="0.3 0 0.2"><freejoint/>', '<body name="ghost" pos="0.3 0 0.2">')
    assert not sand_notes(welded)
    m = mujoco.MjModel.from_xml_string(xml)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mjrft.GranularTerrain(m, "poppy_cp", bodies=["box", "ghost"], resolution=0.01)
    assert not [w for w in caught if issubclass(w.category, mjrft.SandContactWarning)]
