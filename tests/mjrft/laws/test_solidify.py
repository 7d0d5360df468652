"""The solidify option (mjrft/laws/solidify.py): a resting element holds up to f times the law before it flows;
a flowing one feels the law. Each outcome is checked against the option off (the rest memory alone), which
must not show it."""

from __future__ import annotations

import math
import warnings

import mujoco
import pytest

from mjrft import GranularTerrain, TerrainStabilityWarning

DT = 1e-3


def _plate(length=0.0381, width=0.0254, resolution=0.004, extra=""):
    return f"""<mujoco><option timestep="{DT}" integrator="implicitfast"/>
<custom><text name="mjrft:medium" data="poppy_cp"/><text name="mjrft:law" data="rft"/>
<numeric name="mjrft:resolution" data="{resolution}"/></custom>
<worldbody><body name="plate" pos="0 0 0.0032">
<joint name="z" type="slide" axis="0 0 1"/><joint name="pitch" type="hinge" axis="0 1 0"/>
<geom type="box" size="{length / 2} {width / 2} 0.0032" mass="0.02" contype="0" conaffinity="0"/>{extra}
</body></worldbody></mujoco>"""


def _press(factor, program):
    """Li's plate moved kinematically by ``program`` [(duration, vz)]; the lift after each segment."""
    model = mujoco.MjModel.from_xml_string(_plate())
    terrain = GranularTerrain(model, bodies=["plate"], solidify=factor)
    data = mujoco.MjData(model)
    z, out = 0.0, []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        for dur, vz in program:
            for _ in range(int(round(dur / DT))):
                z += vz * DT
                data.qpos[:] = (z, 0.0)
                data.qvel[:] = (vz, 0.0)
                data.time += DT
                mujoco.mj_fwdPosition(model, data)
                mujoco.mj_fwdVelocity(model, data)
                terrain.compute(data, DT)
            out.append(float(terrain.wrench[1, 2]))
    return out


def test_resting_plate_holds_the_static_yield_and_flows_at_the_law():
    # to 2 cm at 1 cm/s, rest 0.1 s, 2 mm more at 0.2 mm/s (at rest: below the stick speed), 1 cm at 1 cm/s
    prog = [(2.0, -0.01), (0.1, 0.0), (10.0, -2e-4), (1.0, -0.01)]
    off = _press(0.0, prog)
    on = _press(2.0, prog)
    assert on[0] == off[0]  # arriving by flowing: the law
    assert off[2] == pytest.approx(off[0] * 2.2 / 2.0, rel=0.1)  # control: the memory alone follows the law
    assert on[2] > 1.9 * off[2]  # solid: twice the law at that depth
    assert on[3] == pytest.approx(off[3], rel=1e-3)  # flowing again: the law itself


def test_factor_one_creeping_plate_follows_the_law():
    prog = [(2.0, -0.01), (0.1, 0.0), (10.0, -2e-4)]
    assert _press(1.0, prog)[-1] == pytest.approx(_press(0.0, prog)[-1], rel=1e-6)


def _pendulum(factor, width=0.304, offset=0.01, t_end=5.0):
    """Thesis fig. 22B: 50 kg at 0.7 m on a 22.9 cm foot, loaded over 2 s, CoM moved ``offset`` over 1 s."""
    xml = _plate(0.229, width, 0.02, '\n<geom type="sphere" pos="0 0 0.7" size="0.05" mass="50" contype="0" '
                                     'conaffinity="0"/>')
    model = mujoco.MjModel.from_xml_string(xml)
    terrain = GranularTerrain(model, bodies=["plate"], solidify=factor)
    data = mujoco.MjData(model)
    x0 = float(model.body_ipos[1, 0])
    weight = float(model.body_subtreemass[1]) * 9.81
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        while data.time < t_end:
            t = data.time
            data.xfrc_applied[1, 2] = weight * max(0.0, 1.0 - t / 2.0)
            model.body_ipos[1, 0] = x0 + offset * min(1.0, max(0.0, t - 2.5))
            terrain.step(data)
            if abs(data.qpos[1]) > 0.5:
                return data.time
    return math.nan


def test_solidified_foot_holds_an_offset_load_that_the_memory_alone_drops():
    assert math.isnan(_pendulum(2.0))  # stands
    assert not math.isnan(_pendulum(0.0))  # control: the rest memory alone falls


def test_static_yield_is_scale_free():
    """The static yield is f times the law's stress, and the load a foot arrives at is the law's stress: the
    margin is the same fraction of the load for every foot, so a narrow foot stands as the wide board does
    (the limit recorded in docs/terrain.md)."""
    assert math.isnan(_pendulum(2.0, width=0.152))


@pytest.mark.parametrize("kw, match", [
    ({"solidify": 0.5}, "solidify must be 0"), ({"solidify": -1.0}, "solidify must be 0"),
    ({"solidify": float("nan")}, "solidify must be 0"), ({"solidify": "x"}, "solidify must be 0"),
    ({"solidify": 2.0, "stick_speed": 0.0}, "stick_speed"),
    ({"solidify": 2.0, "yield_displacement": 0.0}, "rest memory"),
])
def test_bad_solidify_is_refused(kw, match):
    model = mujoco.MjModel.from_xml_string(_plate())
    with pytest.raises(ValueError, match=match):
        GranularTerrain(model, bodies=["plate"], **kw)


def test_solid_element_is_a_spring_for_the_stability_check():
    """Below its static yield a resting element is the memory's spring ``|F_law| / delta`` however much of its
    static yield it holds: the stiffness the kernel sums for the stability check and the implicit step is that
    of the memory at the same depth (``|F_law| / |m|``, the yielding element's, would be 1.5x softer here)."""
    prog = [(2.0, -0.01), (0.1, 0.0), (2.5, -2e-4)]  # 0.5 mm of creep: 1.5 times the law, below f = 2
    out = {}
    for f in (0.0, 2.0):
        model = mujoco.MjModel.from_xml_string(_plate())
        terrain = GranularTerrain(model, bodies=["plate"], solidify=f)
        data = mujoco.MjData(model)
        z = 0.0
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TerrainStabilityWarning)
            for dur, vz in prog:
                for _ in range(int(round(dur / DT))):
                    z += vz * DT
                    data.qpos[:] = (z, 0.0)
                    data.qvel[:] = (vz, 0.0)
                    mujoco.mj_fwdPosition(model, data)
                    mujoco.mj_fwdVelocity(model, data)
                    terrain.compute(data, DT)
        out[f] = (float(terrain.terrain_state.stiff[1, 0]), float(terrain.wrench[1, 2]))
    (k_off, f_off), (k_on, f_on) = out[0.0], out[2.0]
    assert f_on > 1.4 * f_off
    assert k_on == pytest.approx(k_off, rel=0.1)
