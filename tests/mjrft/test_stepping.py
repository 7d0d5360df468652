"""The fused stepping loop (mjrft.stepping): the actuators' power it averages, and its compiled loop steps a terrain
bit for bit as the Python loop of mj_step1, the kernel and mj_step2 does."""

from __future__ import annotations

import mujoco
import numpy as np

import mjrft
from mjrft import coupler
from mjrft.stepping import actuator_power

BOX = """<mujoco><option timestep="0.002"/><worldbody>
<body name="foot" pos="0 0 0.005"><freejoint/><geom name="plate" type="box" size=".05 .05 .005" mass="2"/></body>
</worldbody></mujoco>"""


def test_actuator_power_sums_the_sizes_of_force_times_velocity():
    assert actuator_power(np.array([2.0, -3.0]), np.array([1.5, 2.0])) == 9.0  # the signed sum is -3
    assert actuator_power(np.zeros(0), np.zeros(0)) == 0.0


def test_the_compiled_loop_steps_as_the_python_loop(monkeypatch):
    assert coupler._STEP_FUNCTIONS is not None  # MuJoCo's C functions were found: the compiled loop runs
    runs = []
    for functions in (coupler._STEP_FUNCTIONS, None):  # MuJoCo's C functions, then none: the Python loop
        monkeypatch.setattr(coupler, "_STEP_FUNCTIONS", functions)
        m = mujoco.MjModel.from_xml_string(BOX)
        d = mujoco.MjData(m)
        d.qvel[:3] = [0.05, 0.0, -0.1]
        t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01)
        t.step(d, 150)
        runs.append([d.time, d.qpos.copy(), d.qvel.copy(), t.force.copy(), t.terrain_state.u.copy(), t.wrench.copy()])
    assert coupler._STEP_FUNCTIONS is None and runs[0][0] == runs[1][0]
    for a, b in zip(*runs):
        np.testing.assert_array_equal(a, b)
    # control: the sand carried the plate (free fall for 0.3 s would have taken it 0.47 m down)
    assert np.any(runs[0][3] != 0) and -0.05 < runs[0][1][2] < 0.005
