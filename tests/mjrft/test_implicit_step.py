"""The implicit granular step (GranularTerrain(implicit=True), docs/numerics.md "Implicit step"): the linear
system it solves, rest at steps far beyond the explicit limit, convergence to the explicit step, energy,
and its refusals."""

from __future__ import annotations

import copy
import math
import warnings

import mujoco
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import mjrft
from mjrft import stability

from helpers import (G, LAWS, MEDIA_X, POPPY, assert_finite, chatter, enough, hinged_leg, plate, run, settled_depth,
                     turn_number)

FLAP = """<mujoco><option timestep="{dt}"/><worldbody>
<body name="plate" pos="0 0 0.004"><freejoint/>
  <geom name="sole" type="box" size="0.04 0.04 0.005" mass="0.5"/>
  <body name="flap" pos="0.04 0 0"><joint name="hinge" type="hinge" axis="0 1 0" range="-90 90"/>
    <geom name="blade" type="box" pos="0.02 0 -0.004" size="0.02 0.03 0.003" mass="0.05"/></body>
</body></worldbody></mujoco>"""


def flap(dt=1e-3, implicit=True):
    """A free plate with a light hinged flap, both pressed into poppy seeds and moving."""
    m = mujoco.MjModel.from_xml_string(FLAP.format(dt=dt))
    d = mujoco.MjData(m)
    d.qvel[:3] = (0.02, 0.01, -0.03)
    d.qvel[3:6] = (0.2, -0.1, 0.05)
    d.qvel[6] = -0.5
    return m, d, mjrft.GranularTerrain(m, POPPY, "rft", resolution=0.004, implicit=implicit)


def k6(moments):
    """The 6x6 of springs in every direction with the given moments (stability.add_k6), in numpy."""
    out = np.zeros((6, 6))
    stability.add_k6(out, np.asarray(moments, dtype=float), 1.0)
    return out


def test_applied_wrench_solves_the_linearly_implicit_system():
    """One step from the same state: the implicit terrain applies (I + dt G W)^-1 (F - G dV_o), with F the explicit
    terrain's wrench, G the 6x6 of the kernel's spring moments of each body, W = J M^-1 J^T of the bodies with
    springs (the plate and its flap, coupled through the hinge) and dV_o = dt J qacc_smooth (numpy, from MuJoCo)."""
    m, d0, ti = flap()
    _, _, te = flap(implicit=False)
    di, de, ds = copy.copy(d0), copy.copy(d0), copy.copy(d0)
    te.step(de)
    ti.step(di)
    dt = m.opt.timestep
    mujoco.mj_step1(m, ds)
    mujoco.mj_fwdActuation(m, ds)
    mujoco.mj_fwdAcceleration(m, ds)
    rows = [b for b in ti.body_ids if ti.terrain_state.imp[b, 0] > 0]
    assert len(rows) == 2  # both bodies have elements below yield
    J = np.zeros((6 * len(rows), m.nv))
    for i, b in enumerate(rows):
        mujoco.mj_jacBodyCom(m, ds, J[6 * i:6 * i + 3], J[6 * i + 3:6 * i + 6], int(b))
    minv_jt = np.zeros_like(J)
    mujoco.mj_solveM(m, ds, minv_jt, J)
    W = J @ minv_jt.T
    Gm = np.zeros((6 * len(rows), 6 * len(rows)))
    for i, b in enumerate(rows):
        Gm[6 * i:6 * i + 6, 6 * i:6 * i + 6] = k6(ti.terrain_state.imp[b])
    F = np.concatenate([te.wrench[b] for b in rows])
    expected = np.linalg.solve(np.eye(len(F)) + dt * Gm @ W, F - Gm @ (dt * J @ ds.qacc_smooth))
    applied = np.concatenate([ti.wrench[b] for b in rows])
    np.testing.assert_allclose(applied, expected, rtol=1e-9, atol=1e-12 * np.abs(F).max())
    assert np.abs(applied - F).max() > 1e-3 * np.abs(F).max()  # the correction is not negligible here
    np.testing.assert_array_equal(ti.force, te.force)  # the elements' forces are the explicit evaluation's
    assert not np.array_equal(di.qvel, de.qvel)
    assert np.all(ti.terrain_state.imp[ti.body_ids[0]] == ti.terrain_state.imp[ti.body_ids[0]])  # finite


def rest_run(dt, implicit, mass=1.0, hx=0.05, seconds=1.0):
    """A plate placed at its settled depth in poppy seeds: RMS velocity over the last half, vertical force / weight,
    whether the terrain warned."""
    m, d = plate(mass=mass, hx=hx, dt=dt, bottom=settled_depth(mass, hx, POPPY))
    t = mjrft.GranularTerrain(m, POPPY, "rft", resolution=hx / 2, implicit=implicit)
    rms, warned = chatter(lambda _: (m, d, t), dt, seconds)
    return rms, float(t.wrench[1, 2] / (mass * G)), warned


def test_rest_holds_where_the_explicit_step_chatters():
    """A 1 kg plate resting on poppy seeds at 20 ms, twice its explicit limit (9-12 ms, test_extremes): the explicit
    step chatters and warns; the implicit step holds the plate still, carrying its weight, without a warning."""
    loud, balance, warned = rest_run(0.02, implicit=False)
    assert warned and loud > 1e-2 and abs(balance - 1.0) > 0.05
    quiet, balance, warned = rest_run(0.02, implicit=True)
    assert not warned and quiet < 1e-4 and balance == pytest.approx(1.0, abs=1e-5)


def test_hinged_leg_is_quiet_far_beyond_the_explicit_limit():
    """The leg the explicit check is calibrated on: at 2.5x its limit the explicit step chatters; the implicit step
    at 2.5x and at 25x (26 ms) comes to rest within 300 steps (its buried tip is three times lighter than its centre
    of mass: the implicit step uses the leg's mobility through the hinge, not its mass)."""
    m, d, t = hinged_leg(2e-5, implicit=False)
    t.step(d, 200)
    limit = t.stable_timestep(d)[t.body_ids[0]]
    for factor in (2.5, 25.0):
        dt = factor * limit
        m, d, t = hinged_leg(dt, implicit=True)
        steps = 300
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", mjrft.TerrainStabilityWarning)
            qv = []
            for _ in range(steps):
                t.step(d)
                qv.append(d.qvel[0])
        assert_finite(d, t)
        assert not caught
        assert np.abs(qv[-10:]).max() < 1e-6, factor  # at rest: the oscillation decays instead of chattering


def drop(dt, implicit, seconds=0.25):
    """A 1 kg, 10 cm plate dropped onto poppy seeds at 0.3 m/s: its final depth (m)."""
    m, d = plate(mass=1.0, hx=0.05, dt=dt, bottom=0.0)
    d.qvel[2] = -0.3
    t = mjrft.GranularTerrain(m, POPPY, "rft", resolution=0.01, implicit=implicit)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mjrft.TerrainStabilityWarning)
        t.step(d, int(round(seconds / dt)))
    return m.geom_size[0][2] - d.qpos[2]


def test_converges_to_the_explicit_step():
    """The implicit step is a first-order integrator of the same model: the dropped plate's final depth equals the
    explicit step's at 0.1 ms within 0.05 %, and its error halves with the step (1 % at 1 ms, 2 % at 2 ms; the
    explicit step's own: 0.7 % and 1.6 %)."""
    ref = drop(1e-4, implicit=False)
    assert drop(1e-4, implicit=True) == pytest.approx(ref, rel=5e-4)
    e1 = abs(drop(1e-3, implicit=True) / ref - 1)
    e2 = abs(drop(2e-3, implicit=True) / ref - 1)
    assert e1 < 0.015 and e2 < 0.03 and 1.5 < e2 / e1 < 3.0


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(law=st.sampled_from(LAWS), medium=st.sampled_from(sorted(MEDIA_X)),
       log_mass=st.floats(-3.0, math.log10(500.0)), log_dt=st.floats(-5.0, -2.0),
       log_hx=st.floats(-2.5, -0.5), bottom=st.floats(-0.005, 0.05),
       v=st.tuples(*[st.floats(-10.0, 10.0)] * 3), spin=st.tuples(*[st.floats(-3.0, 3.0)] * 3))
def test_passive_body_never_gains_energy(law, medium, log_mass, log_dt, log_hx, bottom, v, spin):
    """test_extremes' property with the implicit step, in the same scope: a passive body never ends a step with more
    energy than it started with unless the terrain warned (the implicit step warns only about what stays explicit:
    the depth stiffness, docs/numerics.md)."""
    mass, dt, hx = 10.0 ** log_mass, 10.0 ** log_dt, 10.0 ** log_hx
    v = np.array(v)
    if np.linalg.norm(v) > 10.0:
        v *= 10.0 / np.linalg.norm(v)
    assume(turn_number(MEDIA_X[medium], mass, hx, bottom, np.linalg.norm(v), dt) < 0.25)
    assume(mass / (2 * hx) ** 2 >= 1.0)
    assume(law != "depth_only" or dt <= 5e-4)
    m, d = plate(mass=mass, hx=hx, dt=dt, bottom=bottom, integrator="implicit")  # as test_extremes' (its docstring)
    d.qvel[:3] = v
    d.qvel[3:] = spin
    t = mjrft.GranularTerrain(m, MEDIA_X[medium], law, resolution=hx / 2, implicit=True)
    energies, warned = run(m, d, t, enough(150))
    if not warned:
        assert d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number == 0
        scale = mass * G * (2 * hx + abs(bottom)) + abs(energies[0]) + 1e-12
        assert np.max(energies) <= energies[0] + 1e-7 * scale, (energies.max() - energies[0]) / scale


def test_refusals():
    m, d = plate()
    with pytest.raises(TypeError, match="implicit must be True or False, got 'yes'"):
        mjrft.GranularTerrain(m, POPPY, "rft", implicit="yes")
    t = mjrft.GranularTerrain(m, POPPY, "rft", implicit=True)
    with pytest.raises(ValueError, match="install does not support implicit=True"):
        t.install()
    assert mujoco.get_mjcb_passive() is None


def test_batched_equals_one_by_one():
    """mjrft.batch steps implicit terrains through the same compiled loop: bit-identical to stepping each alone."""
    from mjrft.batch import BatchedTerrain

    pairs = [flap() for _ in range(2)]
    alone = [flap() for _ in range(2)]
    batch = BatchedTerrain([t for _, _, t in pairs], [d for _, d, _ in pairs])
    for _ in range(5):
        batch.step(20)
        for m, d, t in alone:
            t.step(d, 20)
    for (_, d1, t1), (_, d2, t2) in zip(pairs, alone):
        np.testing.assert_array_equal(d1.qpos, d2.qpos)
        np.testing.assert_array_equal(t1.wrench, t2.wrench)


def test_a_light_wide_plate_warns_about_the_depth_stiffness():
    """What stays explicit has its limit: a 1 kg plate 27 cm wide placed on the surface at 10 ms bounces higher each
    time on the force that grows with its depth (|F| / depth on 1 mm of sinkage, omega dt = 1.8), and the terrain
    says so."""
    hx = 10 ** -0.875
    m, d = plate(mass=1.0, hx=hx, dt=1e-2, bottom=0.0, integrator="implicit")
    t = mjrft.GranularTerrain(m, POPPY, "rft", resolution=hx / 2, implicit=True)
    with pytest.warns(mjrft.TerrainStabilityWarning, match=r"depth stiffness on body 'foot'"):
        t.step(d, enough(100))
    assert_finite(d, t)
