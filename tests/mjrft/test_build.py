"""A terrain's records (mjrft/types.py, built by mjrft/build.py): one TerrainModel that every path steps, a fresh
TerrainState per world; a change of medium, regions or surface makes a new model and leaves the old one as it was."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.batch import BatchedTerrain
from mjrft.build import build_model, make_state, with_regions, with_surface
from mjrft.models import hexapod_model
from mjrft.types import TerrainModel, TerrainState


def tripod(m, d):
    d.ctrl[:] = 2 * np.pi * 2.0 * d.time + np.arange(m.nu) % 2 * np.pi


def walk(terrain, m, steps=30, each=10):
    d = mujoco.MjData(m)
    out = []
    for _ in range(steps):
        tripod(m, d)
        terrain.step(d, each)
        out.append(np.concatenate([d.qpos, terrain.wrench.ravel()]))
    return np.array(out)


def test_the_model_record_is_frozen_and_built_without_touching_the_mujoco_model():
    m = hexapod_model()
    contype = m.geom_contype.copy()
    tm = build_model(m)
    assert isinstance(tm, TerrainModel) and np.array_equal(m.geom_contype, contype)
    with pytest.raises(dataclasses.FrozenInstanceError):
        tm.stress_scale = 2.0
    el, sf, rg, cs, gr = tm.tables
    assert tm.tables is tm.tables  # one kernel view per model: callers tell models apart by identity
    assert el.lpos.shape == (tm.n_elements, 3) and el.group_start[-1] == tm.n_elements
    assert rg.params.shape[0] == 1 and sf.top == sf.height == 0.0 and not cs.implicit
    assert not gr.on and build_model(hexapod_model(), ground_memory=True).ground.on  # off unless asked
    st = make_state(tm, m)
    assert isinstance(st, TerrainState) and st.u.shape == (tm.n_elements, 3) and st.imp.shape == (0, 10)


def test_a_terrain_from_the_records_steps_as_the_terrain_built_from_the_arguments():
    m = hexapod_model()
    built = mjrft.GranularTerrain(m, "poppy_lp", implicit=True)
    m2 = hexapod_model()
    shared = mjrft.GranularTerrain.from_model(m2, built.terrain_model)  # the same records, a fresh state
    assert shared.terrain_model is built.terrain_model and shared.terrain_state is not built.terrain_state
    assert np.array_equal(walk(built, m), walk(shared, m2))
    # control: another model's records do not step the same
    other = mjrft.GranularTerrain.from_model(hexapod_model(), build_model(hexapod_model(), "poppy_cp", implicit=True))
    assert not np.array_equal(walk(built, m), walk(other, other.model))
    with pytest.raises(ValueError, match="bodies"):
        mjrft.GranularTerrain.from_model(mujoco.MjModel.from_xml_string(
            "<mujoco><worldbody><body><freejoint/><geom size='.1'/></body></worldbody></mujoco>"), built.terrain_model)


def test_batched_terrains_on_one_model_record_equal_their_own_steps():
    tm = build_model(hexapod_model())
    models = [hexapod_model() for _ in range(3)]
    alone = [walk(mjrft.GranularTerrain.from_model(m, tm), m, steps=8) for m in models]
    terrains = [mjrft.GranularTerrain.from_model(m, tm) for m in models]
    datas = [mujoco.MjData(m) for m in models]
    batch = BatchedTerrain(terrains, datas)
    out = [[] for _ in models]
    for _ in range(8):
        for m, d in zip(models, datas):
            tripod(m, d)
        batch.step(10)
        for e, (d, t) in enumerate(zip(datas, terrains)):
            out[e].append(np.concatenate([d.qpos, t.wrench.ravel()]))
    for e in range(3):
        assert np.array_equal(np.array(out[e]), alone[e])


def test_a_change_makes_a_new_model_and_leaves_the_old_one_as_it_was():
    m = hexapod_model()
    t = mjrft.GranularTerrain(m)
    old = t.terrain_model
    params = old.regions.params.copy()
    t.set_medium("glass03_cp", stress_scale=2.0)
    assert t.terrain_model is not old and np.array_equal(old.regions.params, params)
    assert t.terrain_model.elements is old.elements  # the elements are kept
    assert t.stress_scale == 2.0 and t.medium.name == "glass03_cp"
    new = with_regions(old, dataclasses.replace(old.settings, medium=mjrft.get_medium("glass03_cp")), 2.0)
    assert np.array_equal(new.regions.params, t.terrain_model.regions.params)
    raised = with_surface(old, 0.01)
    assert raised.surface.height == raised.surface.top == 0.01 and old.surface.height == 0.0
