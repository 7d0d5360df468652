"""What a terrain says while it steps (mjrft/watch.py): the checks run within a fixed span of simulated time, on the
first step of a short loop too, and each warning's advice holds at the step in use (docs/numerics.md)."""

from __future__ import annotations

import os
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.coupler import STABILITY_CHECK_EVERY, STABILITY_CHECK_SPAN
from mjrft.stability import CHATTER_MIN_STEPS, CHATTER_STEPS, chatter_steps
from mjrft.watch import StabilityWatch

BOX = """<mujoco><option timestep="{dt}"/><worldbody>
<body name="box" pos="0 0 0.06"><freejoint/><geom type="box" size=".05 .05 .05" mass="1"/></body></worldbody></mujoco>"""
QUADRUPED = os.path.join(os.path.dirname(mjrft.models.__file__), "third_party", "dm_quadruped", "quadruped.xml")


def stability_warnings(make_terrain, dt: float, steps: int) -> list[str]:
    """The TerrainStabilityWarnings of ``steps`` single steps of a 1 kg box dropped onto poppy seeds at ``dt``."""
    m = mujoco.MjModel.from_xml_string(BOX.format(dt=dt))
    d = mujoco.MjData(m)
    t = make_terrain(m)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(steps):
            t.step(d, 1)
    return [str(w.message) for w in caught if issubclass(w.category, mjrft.TerrainStabilityWarning)]


def test_checks_run_every_step_at_a_large_timestep_and_every_50_at_a_small_one(monkeypatch):
    assert STABILITY_CHECK_EVERY * 1e-3 <= STABILITY_CHECK_SPAN  # at 1 ms and below the step count decides
    calls = []
    monkeypatch.setattr(StabilityWatch, "check", lambda self, data, *a: calls.append(data.time))  # the schedule only
    m = mujoco.MjModel.from_xml_string(BOX.format(dt=0.05))
    t = mjrft.GranularTerrain(m, "poppy_cp")
    d = mujoco.MjData(m)
    for _ in range(4):
        t.step(d, 1)
    assert len(calls) == 4  # 50 ms apart: every step
    m.opt.timestep = 1e-3
    t.reset()
    calls.clear()
    for _ in range(120):
        t.step(d, 1)
    assert len(calls) == 3  # after the reset, then at 50 and 100 steps


@pytest.mark.filterwarnings("ignore::mjrft.ValidityRangeWarning")
def test_an_unstable_step_is_heard_of_in_a_short_loop_with_advice_that_holds_for_it():
    # a 1 kg box on poppy seeds at 50 ms: its springs' and its depth stiffness's limits are both exceeded
    explicit = stability_warnings(lambda m: mjrft.GranularTerrain(m, "poppy_cp"), 0.05, 5)
    assert len(explicit) == 1, explicit
    assert "below" in explicit[0]
    assert "implicit step (implicit=True) alone would not make this step stable" in explicit[0]
    implicit = stability_warnings(lambda m: mjrft.GranularTerrain(m, "poppy_cp", implicit=True), 0.05, 5)
    assert len(implicit) == 1 and "depth stiffness" in implicit[0], implicit
    # control: the same drop at 1 ms says nothing
    assert not stability_warnings(lambda m: mjrft.GranularTerrain(m, "poppy_cp"), 1e-3, 300)


def test_the_springs_warning_names_the_implicit_step_where_it_is_the_cure():
    # a 1 kg plate resting at 20 ms: beyond its springs' limit, within its depth stiffness's
    hx = 0.05
    xml = BOX.format(dt=0.02).replace('size=".05 .05 .05"', f'size="{hx} {hx} 0.0125"').replace("0.06", "0.0125")
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    t = mjrft.GranularTerrain(m, "poppy_cp")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        t.step(d, 100)
    text = [str(w.message) for w in caught if issubclass(w.category, mjrft.TerrainStabilityWarning)]
    assert text and "implicit=True), which removes this limit" in text[0], text
    assert "would not make this step stable" not in text[0]


def test_chatter_is_reported_within_a_span_of_simulated_time():
    assert chatter_steps(5e-4) == chatter_steps(2e-3) == CHATTER_STEPS
    assert chatter_steps(0.02) == 10 and chatter_steps(0.1) == CHATTER_MIN_STEPS
    from mjrft.stability import TRACK_SLOTS, chattering, track_chatter

    wrench, slots, bodies = np.zeros((2, 6)), np.zeros((2, TRACK_SLOTS, 10)), np.array([1])
    for k in range(13):  # 12 reversals of +-50 %
        wrench[1, 2] = 100.0 + (50.0 if k % 2 else -50.0)
        track_chatter(wrench, bodies, slots)
    assert chattering(slots.copy(), bodies, chatter_steps(0.02))  # 0.24 s at 20 ms: chatter
    assert not chattering(slots, bodies, chatter_steps(1e-3))  # 12 ms at 1 ms: a transient


@pytest.mark.filterwarnings("ignore::mjrft.ValidityRangeWarning", "ignore::mjrft.SandContactWarning")
def test_a_quadruped_chattering_at_four_times_its_step_is_warned_within_a_second():
    def chatter_time(scale: float, seconds: float) -> float:
        m = mujoco.MjModel.from_xml_path(QUADRUPED)
        m.opt.timestep *= scale
        m.geom_contype[m.geom("terrain").id] = m.geom_conaffinity[m.geom("terrain").id] = 0  # sand all the way down
        d = mujoco.MjData(m)
        t = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=True)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            while d.time < seconds:
                t.step(d, 1)
                if any("chatters" in str(w.message) for w in caught):
                    assert "halve the timestep" in str(caught[-1].message)
                    return d.time
        return np.inf

    assert chatter_time(4.0, 1.5) < 1.2  # dm_control's quadruped at 20 ms: its feet alternate 0-4 x its weight
    assert chatter_time(1.0, 1.5) == np.inf  # control: at its own 5 ms the implicit step rests quietly
