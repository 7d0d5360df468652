"""The terrain's records (mjrft.types): a TerrainModel is frozen, its kernels' view (``tables``) is one object per
model holding its tables, and a model without a ground memory carries empty ground tables."""

from __future__ import annotations

import dataclasses

import mujoco
import pytest

from mjrft.build import build_model, make_state
from mjrft.types import TerrainModel, TerrainState, TerrainTables, no_ground

BOX = """<mujoco><worldbody><body name="foot" pos="0 0 0.01"><freejoint/>
<geom name="plate" type="box" size=".02 .02 .005" mass="0.2"/></body></worldbody></mujoco>"""


def test_the_model_is_frozen_and_its_tables_are_one_view_per_model():
    m = mujoco.MjModel.from_xml_string(BOX)
    tm = build_model(m, "poppy_cp", "rft", resolution=0.01)
    assert isinstance(tm, TerrainModel) and tm.n_elements == tm.elements.area.shape[0] > 0
    with pytest.raises(dataclasses.FrozenInstanceError):
        tm.stress_scale = 2.0
    tables = tm.tables
    assert isinstance(tables, TerrainTables) and tm.tables is tables
    assert all(a is b for a, b in zip(tables, (tm.elements, tm.surface, tm.regions, tm.constants, tm.ground)))
    # control: another model (even of the same MjModel) is told apart by its tables' identity
    assert build_model(m, "poppy_cp", "rft", resolution=0.01).tables is not tables
    changed = dataclasses.replace(tm, stress_scale=2.0)
    assert changed.tables is not tables and tm.stress_scale == 1.0
    st = make_state(tm, m)
    assert isinstance(st, TerrainState) and st.u.shape == (tm.n_elements, 3)


def test_without_a_ground_memory_the_ground_tables_are_empty():
    g = no_ground()
    assert not g.on and g.base.size == 0 and g.dparams.size == 0
    tm = build_model(mujoco.MjModel.from_xml_string(BOX), "poppy_cp", "rft", resolution=0.01)
    assert not tm.ground.on
    assert build_model(mujoco.MjModel.from_xml_string(BOX), "poppy_cp", "rft", resolution=0.01,
                       ground_memory=True).ground.on
