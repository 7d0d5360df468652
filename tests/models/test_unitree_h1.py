"""A humanoid whose feet collide through a triangle mesh, on sand: Unitree's H1 (their MuJoCo model, vendored with
its foot mesh under models/third_party/unitree_h1/), held by ``mjrft.models.unitree_h1.Controller`` (joint PD
around the keyframe, leaning over the soles, ankle balance) at the model's own 2 ms step with the implicit
granular step (``GranularTerrain(model, "poppy_cp", bodies=FEET, floor="auto", implicit=True)``)."""

from __future__ import annotations

import os
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.errors import TerrainStabilityWarning, ValidityRangeWarning
from mjrft.models import unitree_h1 as h1

MASS = 51.649896  # kg: the robot's <inertial> masses (the 0.1 kg "not_use_body" at z = 20 m is not part of it)
REST = 0.5  # s: the window at the end of a run over which the load is averaged


def h1_on(sand: bool = True, implicit: bool = True):
    """(model, data leaning over the soles at the floor's height, the controller, the terrain or None)."""
    m, d = h1.load()
    ctl = h1.Controller(m)
    ctl.reset(d)
    terrain = None
    if sand:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ValidityRangeWarning)
            terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", bodies=list(h1.FEET), implicit=implicit)
    return m, d, ctl, terrain


def weight(m) -> float:
    return float(m.body_subtreemass[m.body("pelvis").id]) * -float(m.opt.gravity[2])


def run(m, d, ctl, terrain, seconds: float, pattern=None) -> tuple[np.ndarray, np.ndarray]:
    """Step ``seconds``; per step the net vertical granular force over the weight and each foot's share."""
    n = int(round(seconds / m.opt.timestep))
    load, feet = np.empty(n), np.empty((n, 2))
    ids = [m.body(f).id for f in h1.FEET]
    t0 = d.time
    for i in range(n):
        ctl(d, None if pattern is None else pattern(d.time - t0))
        terrain.step(d)  # raises NonFiniteError on a non-finite state or force
        load[i] = terrain.wrench[:, 2].sum() / weight(m)
        feet[i] = terrain.wrench[ids, 2] / weight(m)
    return load, feet


# ----------------------------------------------------------------- the vendored model


def test_vendored_h1_keeps_the_foot_meshes_and_inertials():
    m, d = h1.load()
    assert os.path.isfile(os.path.join(h1.H1_DIR, "LICENSE")) and os.path.isfile(os.path.join(h1.H1_DIR, "README.md"))
    assert m.opt.timestep == 0.002 and m.nu == 20 and m.nkey == 1
    feet = [m.body(f).id for f in h1.FEET]
    foot_geoms = [g for g in range(m.ngeom) if m.geom_bodyid[g] in feet]
    assert len(foot_geoms) == 2 and all(m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH for g in foot_geoms)
    assert all(m.geom_contype[g] and m.geom_conaffinity[g] for g in foot_geoms)
    assert m.mesh_facenum.tolist() == [8788, 8788]  # the STL's triangles, both feet from the one file
    assert float(m.body_subtreemass[m.body("pelvis").id]) == pytest.approx(MASS, rel=1e-9)


def test_h1_stands_on_its_rigid_floor():
    """Control: the same controller on MuJoCo's floor holds the robot up with the sole meshes' contacts."""
    m, d, ctl, _ = h1_on(sand=False)
    for _ in range(int(round(2.0 / m.opt.timestep))):
        ctl(d)
        mujoco.mj_step(m, d)
    assert d.ncon >= 4 and 0.95 < d.qpos[2] < 1.0 and np.abs(d.qvel).max() < 0.05  # measured 0.976 m, 8 contacts
    assert abs(h1.pelvis_pitch(d) - ctl.lean) < 0.02  # measured 0.005


def test_h1_without_its_balance_term_tips_over_on_the_rigid_floor():
    """Control for the controller: the joint PD alone (no lean, no balance term) lets it topple backwards."""
    m, d = h1.load()
    ctl = h1.Controller(m, balance_kp=0.0, balance_kd=0.0)
    ctl.home = m.key("home").qpos[ctl.qadr].copy()
    for _ in range(int(round(2.0 / m.opt.timestep))):
        ctl(d)
        mujoco.mj_step(m, d)
    assert h1.pelvis_pitch(d) < -0.5  # measured -1.3


# ----------------------------------------------------------------- on sand


def test_h1_stands_on_sand_and_carries_its_weight():
    m, d, ctl, terrain = h1_on()
    floor = m.geom("floor").id
    assert terrain.floor == floor and (m.geom_contype[floor], m.geom_conaffinity[floor]) == (0, 0)
    assert set(m.geom_bodyid[terrain.elem_geom]) == {m.body(f).id for f in h1.FEET}
    with warnings.catch_warnings():
        warnings.simplefilter("error", TerrainStabilityWarning)  # the implicit step is stable at 2 ms
        warnings.simplefilter("ignore", ValidityRangeWarning)  # the feet go deeper than Li 2013's plates did
        load, feet = run(m, d, ctl, terrain, 2.0)
    rest = load[-int(round(REST / m.opt.timestep)):]
    assert abs(rest.mean() - 1.0) < 0.005  # measured 0.99996
    assert load.max() < 3.0  # the landing from the floor's height (measured 2.04)
    assert np.abs(rest - 1.0).max() < 0.01  # every step of the last 0.5 s (measured 4.8e-4)
    assert np.all(np.abs(feet[-1] - 0.5) < 0.05)  # the two feet share it (measured 0.504 / 0.497)
    assert np.abs(d.qvel).max() < 0.05 and d.ncon == 0  # at rest on the grains alone
    sink = terrain.sinkage()[[m.body(f).id for f in h1.FEET]]
    assert np.all((0.10 < sink) & (sink < 0.16))  # measured 132 mm: the 3 cm wide soles sink deep in loose grains
    assert abs(h1.pelvis_pitch(d) - ctl.lean) < 0.05 and abs(ctl.com_offset(d)) < 0.02  # upright over its soles


def test_h1_explicit_step_at_2ms_is_past_its_limit():
    """Control for the per-step bound: the explicit granular step at the model's 2 ms is beyond the soles'
    stability limit (0.76 ms); the terrain says so and the load swings from step to step (it does not diverge)."""
    m, d, ctl, terrain = h1_on(implicit=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load, _ = run(m, d, ctl, terrain, 2.0)
    assert any(issubclass(w.category, TerrainStabilityWarning) and "ankle_link" in str(w.message) for w in caught)
    rest = load[-int(round(REST / m.opt.timestep)):]
    assert np.ptp(rest) > 0.1  # measured 0.91 to 1.09 times the weight


def test_h1_without_the_granular_force_falls_through_the_surface():
    """Control: the floor's contacts are gone, so nothing but the grains holds the robot up."""
    m, d, ctl, terrain = h1_on()
    for _ in range(int(round(1.0 / m.opt.timestep))):
        ctl(d)
        mujoco.mj_step(m, d)
    assert d.qpos[2] < -2.0 and d.ncon == 0  # measured -3.9 m


@pytest.mark.slow
def test_h1_without_the_lean_tips_backwards_on_sand():
    """The keyframe's centre of mass is 6 cm behind the soles' centroid, outside their middle third: on the
    yielding bed the heels sink and the robot tips backwards (measured), which is why the controller leans."""
    m, d = h1.load()
    ctl = h1.Controller(m)
    ctl.home[ctl.ankles] += ctl.lean  # the keyframe's ankles: no lean
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityRangeWarning)
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", bodies=list(h1.FEET), implicit=True)
        for _ in range(int(round(2.0 / m.opt.timestep))):
            ctl(d)
            terrain.step(d)
    assert h1.pelvis_pitch(d) < -0.5  # measured -3.1: on its back


@pytest.mark.slow
def test_h1_shifts_its_weight_from_foot_to_foot_on_sand():
    """An open-loop sway (hip rolls 0.05 rad at 0.5 Hz) with the unloaded knee bending 0.1 rad, for 4 s after
    settling: no divergence, each foot unloaded in turn. The feet stay in the sand (13-16 cm deep): lifting them
    out of it (0.25 rad at 1 Hz) sends the pelvis 0.45 m sideways within 1.5 s (measured; its soles are 3 cm wide
    and the controller has no lateral balance)."""
    m, d, ctl, terrain = h1_on()
    with warnings.catch_warnings():
        warnings.simplefilter("error", TerrainStabilityWarning)
        warnings.simplefilter("ignore", ValidityRangeWarning)
        run(m, d, ctl, terrain, 1.0)
        start = d.qpos[:3].copy()
        load, feet = run(m, d, ctl, terrain, 4.0, lambda t: ctl.step_targets(t, sway=0.05, lift=0.1, freq=0.5))
    assert np.all(np.isfinite(d.qpos)) and abs(h1.pelvis_pitch(d)) < 0.15  # measured 0.015
    assert np.linalg.norm(d.qpos[:2] - start[:2]) < 0.1  # stays in place (measured 0.037 m)
    assert abs(load.mean() - 1.0) < 0.05  # the grains carry it throughout (measured 0.9999)
    assert feet[:, 0].min() < 0.3 and feet[:, 1].min() < 0.3  # each foot under 30 % at times (measured 3 %, 2 %)
    assert feet[:, 0].max() > 0.7 and feet[:, 1].max() > 0.7


def walk(m, d, ctl, terrain, steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hold the pose 1 s, then ``Controller.walk`` for ``steps`` steps and 1 s standing; the pelvis' start
    position, per step each foot's vertical granular force over the weight and the pelvis' tilt from the vertical
    (rad). Stops at a tilt over 1 rad."""
    ids = [m.body(f).id for f in h1.FEET]
    with warnings.catch_warnings():
        warnings.simplefilter("error", TerrainStabilityWarning)
        warnings.simplefilter("ignore", ValidityRangeWarning)
        run(m, d, ctl, terrain, 1.0)
        start, t0 = d.qpos[:3].copy(), d.time
        n = int(round((steps * sum(h1.WALK_PHASES) + 1.0) / m.opt.timestep))
        feet, tilt = np.full((n, 2), np.nan), np.full(n, np.nan)
        for i in range(n):
            ctl.walk(d, d.time - t0, steps=steps, length=0.05)
            terrain.step(d)  # raises NonFiniteError on a non-finite state or force
            feet[i] = terrain.wrench[ids, 2] / weight(m)
            tilt[i] = np.arccos(np.clip(d.xmat[1][8], -1.0, 1.0))
            if tilt[i] > 1.0:
                break
    return start, feet, tilt


@pytest.mark.slow
def test_h1_walks_two_steps_forward_on_sand():
    """The quasi-static walk: two steps of 5 cm (each foot unloaded and lifted in turn), then standing."""
    m, d, ctl, terrain = h1_on()
    start, feet, tilt = walk(m, d, ctl, terrain, steps=2)
    assert np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel)) and np.isfinite(tilt).all()
    assert np.all(feet.min(0) < 0.02)  # each foot carries nothing at times (measured -0.83, -0.22: pulled down)
    assert d.qpos[0] - start[0] > 0.07 and abs(d.qpos[1] - start[1]) < 0.05  # measured 0.101 m, -0.030 m
    assert tilt.max() < 0.25  # from the vertical, the 0.069 rad lean included (measured 0.177)
    assert abs(h1.pelvis_pitch(d) - ctl.lean) < 0.03 and abs(h1.pelvis_roll(d)) < 0.03  # measured 0.010, 0.005
    assert np.all(np.abs(feet[-1] - 0.5) < 0.1)  # standing on both (measured 0.52 / 0.48)


@pytest.mark.slow
def test_h1_walk_without_the_hip_roll_shift_tips_over():
    """Control: the same walk with the hip rolls not turned towards the stance foot (``walk_roll = 0``) falls
    sideways once the first foot lifts."""
    m, d, ctl, terrain = h1_on()
    ctl.walk_roll = 0.0
    start, feet, tilt = walk(m, d, ctl, terrain, steps=2)
    assert np.nanmax(tilt) > 1.0 and d.qpos[1] - start[1] > 0.5  # measured 2.5 s into the walk, 0.79 m to its left
