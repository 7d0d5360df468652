"""Two third-party quadrupeds on sand at their own timesteps (:mod:`mjrft.models.quadrupeds`): MuJoCo Menagerie's
ANYmal C (2 ms) and dm_control's quadruped (5 ms), vendored under models/third_party/ with their licences.

Each rests on poppy seeds with the implicit granular step carrying its weight within 2 % on EVERY step of the
last second (not only on average), and the same check rejects the explicit step at the same timestep (the
granular force alternates from step to step). The chatter detection (:func:`mjrft.stability.track_chatter`)
warns on the explicit step's chatter, naming the body, the timestep and the cure, and stays silent on the
quadruped at rest with the implicit step. Each walks 3 s under an open-loop trot without diverging."""

from __future__ import annotations

import os
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.errors import TerrainStabilityWarning, ValidityRangeWarning
from mjrft.models import quadrupeds as q

ROBOTS = ("anymal_c", "dm_quadruped")
TIMESTEP = {"anymal_c": 0.002, "dm_quadruped": 0.005}  # the models' own
MASS = {"anymal_c": 44.96518, "dm_quadruped": 107.1179}  # kg, the compiled models' total mass
FACING = {"anymal_c": -1.0, "dm_quadruped": 1.0}  # the x direction each faces (ANYmal C's base is turned 180 deg)


def weight(m) -> float:
    return float(m.body_subtreemass[0]) * -float(m.opt.gravity[2])


def stand(name: str, implicit: bool, seconds: float = 3.0):
    """(model, data, terrain, load at every step, the TerrainStabilityWarnings' texts): the robot from its model's
    initial state with ``ctrl = 0`` on poppy seeds for ``seconds``."""
    m = q.MODELS[name]()
    d = mujoco.MjData(m)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=implicit)
        load = np.empty(int(round(seconds / m.opt.timestep)))
        for i in range(len(load)):
            terrain.step(d)
            load[i] = terrain.wrench[:, 2].sum() / weight(m)
    texts = [str(w.message) for w in caught if issubclass(w.category, TerrainStabilityWarning)]
    return m, d, terrain, load, texts


def last_second(m, load) -> np.ndarray:
    return load[-int(round(1.0 / m.opt.timestep)):]


# ----------------------------------------------------------------- the vendored models


def test_vendored_quadrupeds_keep_their_licences_and_collision_geometry():
    for folder in (q.ANYMAL_C_DIR, q.DM_QUADRUPED_DIR):
        assert os.path.isfile(os.path.join(folder, "LICENSE")) and os.path.isfile(os.path.join(folder, "README.md"))
    assert "ANYbotics" in open(os.path.join(q.ANYMAL_C_DIR, "LICENSE")).read()
    assert "Apache License" in open(os.path.join(q.DM_QUADRUPED_DIR, "LICENSE")).read()
    for name in ROBOTS:
        m = q.MODELS[name]()
        assert m.opt.timestep == TIMESTEP[name] and m.nu == 12 and m.nmesh == 0
        assert float(m.body_subtreemass[0]) == pytest.approx(MASS[name], rel=1e-6)
        assert all(m.body(f).id > 0 for f in q.FEET[name])
    a = q.anymal_c_model()  # 4 foot spheres of 3 cm among the collision primitives
    feet = [g for g in range(a.ngeom) if a.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE]
    assert len(feet) == 4 and all(a.geom_size[g, 0] == 0.03 for g in feet)
    dq = q.dm_quadruped_model()  # dm_control's walk task: no walls, ball, height-field geom or rangefinders
    assert dq.nhfield == 1 and dq.ngeom == 1 + 2 + 1 + 16 and dq.neq == 4 and dq.nsensor == 12
    with pytest.raises(ValueError, match="no trot for robot 'go2'"):
        q.trot_ctrl("go2", dq, 0.0)


# ----------------------------------------------------------------- at rest


@pytest.mark.parametrize("name", ROBOTS)
def test_quadruped_rests_on_sand_carrying_its_weight_on_every_step(name):
    m, d, terrain, load, texts = stand(name, implicit=True)
    rest = last_second(m, load)
    assert np.abs(rest - 1.0).max() < 0.02  # every step (measured 6.6e-7, 5.8e-5: rest_balance.txt)
    assert np.all(np.isfinite(d.qpos)) and np.abs(d.qvel).max() < 0.01 and d.ncon == 0
    feet = [m.body(f).id for f in q.FEET[name]]
    assert terrain.wrench[feet, 2].sum() / weight(m) > 0.8  # the feet carry it
    assert d.xmat[1][8] > 0.99  # upright
    assert 0.0 < terrain.sinkage()[feet].min() and terrain.sinkage()[feet].max() < 0.3
    assert not texts  # neither the stability limit (the implicit step's is the depth stiffness's) nor chatter


@pytest.mark.parametrize("name", ROBOTS)
def test_the_explicit_step_at_the_same_timestep_chatters_and_is_warned_about(name):
    """Control for the every-step check above: the explicit step at the model's own timestep alternates the
    load from step to step (its average is still the weight), and the chatter detection names the body, the
    timestep and the cure."""
    m, d, terrain, load, texts = stand(name, implicit=False)
    rest = last_second(m, load)
    assert abs(rest.mean() - 1.0) < 0.02 and np.abs(rest - 1.0).max() > 0.2
    assert np.all(np.sign(np.diff(rest[-10:])) * np.sign(np.diff(rest[-11:-1])) < 0)  # period 2
    chatter = [t for t in texts if "chatters" in t]
    feet = q.FEET[name]
    assert chatter and all(any(f"'{f}'" in t for t in chatter) for f in feet[:1])
    assert all(f"timestep {m.opt.timestep:g} s" in t and "implicit=True" in t for t in chatter)


def test_chatter_check_is_silent_on_a_resolved_rest():
    """dm_control's quadruped with the implicit step at its 5 ms, from the landing on: no warning, and the load
    within 1e-3 of the weight on every step of the last second."""
    m, d, terrain, load, texts = stand("dm_quadruped", implicit=True)
    assert not texts and np.abs(last_second(m, load) - 1.0).max() < 1e-3  # measured 5.8e-5


# ----------------------------------------------------------------- walking


@pytest.mark.slow
@pytest.mark.parametrize("name", ROBOTS)
def test_quadruped_trots_on_sand_without_diverging(name):
    m = q.MODELS[name]()
    d = mujoco.MjData(m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityRangeWarning)
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        terrain = mjrft.GranularTerrain(m, "poppy_cp", floor="auto", implicit=True)
        terrain.step(d, int(round(1.0 / m.opt.timestep)))  # settle
        start, t0, load = d.qpos[:3].copy(), d.time, []
        for _ in range(int(round(3.0 / m.opt.timestep))):
            d.ctrl[:] = q.trot_ctrl(name, m, d.time - t0)
            terrain.step(d)  # raises NonFiniteError on a non-finite state or force
            load.append(terrain.wrench[:, 2].sum() / weight(m))
            assert d.xmat[1][8] > 0.9 and np.abs(d.qvel).max() < 50.0, d.time  # upright, no blow-up
    forward = (d.qpos[0] - start[0]) * FACING[name]
    assert forward > 0.05  # measured 0.104 m (ANYmal C), 0.670 m (quadruped) in 3 s: rest_balance.txt
    assert abs(np.mean(load) - 1.0) < 0.05  # the grains carry it through the gait (measured 1.010, 1.008)
