"""Batched granular stepping (mjrft.batch): BatchedTerrain steps many terrains, each with its own MjData, in one
compiled call (threaded or serial), bit for bit as each terrain alone; its errors name the environment."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft import coupler
from mjrft.batch import BatchedTerrain
from mjrft.models import hexapod_xml

BOX = """<mujoco><option timestep="0.002"/><worldbody>
<body name="foot" pos="0 0 0"><freejoint/><geom name="plate" type="box" size=".05 .05 .005" mass="2"/></body>
</worldbody></mujoco>"""


def hexapods(n, shared_model=True):
    xml = hexapod_xml()
    models = [mujoco.MjModel.from_xml_string(xml)] * n if shared_model else [
        mujoco.MjModel.from_xml_string(xml) for _ in range(n)]
    datas = [mujoco.MjData(m) for m in models]
    terrains = [mjrft.GranularTerrain(m) for m in models]
    return models, datas, terrains


def state(d, t):
    return [d.time, d.qpos, d.qvel, d.act, d.ctrl, d.xfrc_applied, t.force, t.depth, t.terrain_state.u, t.wrench]


def assert_same(a, b):
    for x, y in zip(a, b):
        assert np.array_equal(x, y), (x, y)


@pytest.mark.slow
def test_batched_equals_single_bit_for_bit():
    E = 3
    _, dats, ters = hexapods(E)
    models, refd, reft = hexapods(E, shared_model=False)
    batch = BatchedTerrain(ters, dats)
    rng = np.random.default_rng(0)
    for k in range(9):
        ctrl = rng.uniform(-1.0, 1.0, size=(E, models[0].nu))
        nstep = np.array([10, 10 - k % 3, 0 if k % 4 == 1 else 7])  # per-env counts, some idle
        for e in range(E):
            dats[e].ctrl[:] = ctrl[e]
            refd[e].ctrl[:] = ctrl[e]
            reft[e].step(refd[e], int(nstep[e]))
        batch.parallel = bool(k % 2)  # serial and threaded calls interleaved
        batch.step(nstep)
        for e in range(E):
            assert_same(state(dats[e], ters[e]), state(refd[e], reft[e]))
    assert max(t.n_elements for t in ters) > 100 and any(t.contact_mask().any() for t in ters)
    # after a reset of one env (time goes back) its memory is cleared, as in GranularTerrain.step
    for d in (dats[1], refd[1]):
        mujoco.mj_resetData(models[0], d)
    batch.step(5)
    for e in range(E):
        reft[e].step(refd[e], 5)
        assert_same(state(dats[e], ters[e]), state(refd[e], reft[e]))


def test_batched_follows_changed_arguments_and_python_fallback(monkeypatch):
    models, dats, ters = hexapods(2, shared_model=False)
    refm, refd, reft = hexapods(2, shared_model=False)
    for e in range(2):
        reft[e].step(refd[e], 20)
    refm[1].opt.timestep = 0.0005
    for e in range(2):
        reft[e].step(refd[e], 20)
    batch = BatchedTerrain(ters, dats, parallel=False)
    batch.step(20)
    models[1].opt.timestep = 0.0005  # env 1's argument tuple changes (dt): its list item is replaced
    batch.step(20)
    monkeypatch.setattr(coupler, "_STEP_FUNCTIONS", None)  # no libmujoco to call: each terrain's Python loop
    batch.step(3)
    for e in range(2):
        reft[e].step(refd[e], 3)
    for e in range(2):
        assert_same(state(dats[e], ters[e]), state(refd[e], reft[e]))
    assert dats[1].time == pytest.approx(20 * 0.001 + 23 * 0.0005)


def test_python_callback_keeps_threads_off():
    from mjrft.batch import python_callbacks_installed

    _, dats, ters = hexapods(2)
    _, refd, reft = hexapods(2)
    calls = []
    mujoco.set_mjcb_control(lambda m, d: calls.append(d.time))  # Python: needs the GIL, so no worker threads
    try:
        assert python_callbacks_installed() == ["mjcb_control"]
        BatchedTerrain(ters, dats, parallel=True).step(3)
        for d, t in zip(refd, reft):
            t.step(d, 3)
    finally:
        mujoco.set_mjcb_control(None)
    assert python_callbacks_installed() == [] and len(calls) == 12
    for e in range(2):
        assert_same(state(dats[e], ters[e]), state(refd[e], reft[e]))


@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")
def test_batched_nonfinite_names_env_body_and_time():
    huge = mjrft.Medium("huge", tuple(c * 5e302 for c in mjrft.generic.coeffs), 1e308)  # finite, sums overflow
    models = [mujoco.MjModel.from_xml_string(BOX) for _ in range(3)]
    datas = [mujoco.MjData(m) for m in models]
    terrains = [mjrft.GranularTerrain(m, med, "rft") for m, med in zip(models, ["poppy_cp", huge, "poppy_cp"])]
    for d in datas:
        d.qvel[2] = -0.1
    batch = BatchedTerrain(terrains, datas)
    with pytest.raises(mjrft.NonFiniteError,
                       match=r"^environment 1: non-finite granular force on body 'foot' at t = 0 s") as err:
        batch.step(4)
    assert err.value.env_indices == [1]
    assert np.all(datas[1].xfrc_applied == 0) and datas[1].time == 0.0
    assert datas[0].time == datas[2].time == pytest.approx(0.008)  # the others finished their steps


def test_batched_bad_input():
    _, dats, ters = hexapods(2)
    with pytest.raises(ValueError, match="2 terrains but 1 MjData"):
        BatchedTerrain(ters, dats[:1])
    with pytest.raises(ValueError, match="environments 0 and 1 share one MjData"):
        BatchedTerrain(ters, [dats[0], dats[0]])
    with pytest.raises(TypeError, match="environment 1: terrain must be a mjrft.GranularTerrain"):
        BatchedTerrain([ters[0], None], dats)
    with pytest.raises(ValueError, match="at least one"):
        BatchedTerrain([], [])
    m = mujoco.MjModel.from_xml_string(BOX)
    with pytest.raises(ValueError, match="environment 1: data does not belong"):
        BatchedTerrain(ters, [dats[0], mujoco.MjData(m)])
    batch = BatchedTerrain(ters, dats)
    with pytest.raises(ValueError, match="nstep must be >= 0, got -1 for environment 1"):
        batch.step([2, -1])
    with pytest.raises(ValueError, match="one per environment"):
        batch.step([1, 2, 3])
    with pytest.raises(ValueError, match="one per environment"):
        batch.step(1.5)
    with pytest.raises(ValueError, match="parallel must be True or False"):
        BatchedTerrain(ters, dats, parallel="yes")
    # unlike terrains (a different dtype in one of the arrays the kernel gets) cannot share one compiled call
    st = ters[1].terrain_state
    ters[1].terrain_state = st._replace(group_active=st.group_active.astype(np.int8))
    with pytest.raises(ValueError, match="environment 1's terrain arrays have different types from environment 0's"):
        batch.step(1)
