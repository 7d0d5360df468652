"""The terrain kernel (mjrft.kernel): its pass for dry groups of one Li-RFT region gives what its general pass
gives, reports a non-finite position, and is what a group in the dry strip of a scene with wet strips takes."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import mjrft


@pytest.mark.filterwarnings("ignore::mjrft.TerrainStabilityWarning")  # the viscous mode at 1 ms on a leg
@pytest.mark.parametrize("yield_displacement", [None, 0.0])  # the elastic-plastic memory and the viscous mode
def test_flat_dry_pass_equals_general_loop(yield_displacement):
    """The kernel's pass 2 written out for dry groups (one dry Li-RFT region) gives what its general
    pass 2 gives. The general one is reached through a region map (never specialised) of one cell
    holding the same medium and law: same physics, other code path. Compared on every step of a
    walking hexapod whose legs enter and leave the sand (cull groups switching on and off included). Both
    terrains are implicit, so the implicit step's spring moments (summed per body in the batched pass, element by
    element in the general one) are compared too."""
    from mjrft.regions import RegionMap
    from mjrft.models import hexapod_model
    m = hexapod_model()
    d = mujoco.MjData(m)
    fast = mjrft.GranularTerrain(m, resolution=0.008, yield_displacement=yield_displacement, implicit=True)
    general = mjrft.GranularTerrain(m, resolution=0.008, yield_displacement=yield_displacement, implicit=True,
                                    regions=[mjrft.Region(None, fast.medium, "rft")],
                                    region_map=RegionMap(np.ones((1, 1), dtype=np.int64), -10.0, -10.0, 20.0))
    assert general.terrain_model.regions.law.shape[0] == 2 and fast.terrain_model.regions.law.shape[0] == 1
    assert general.terrain_model.regions.map.size == 1
    rows = fast.body_ids
    left = entered = springs = 0
    for k in range(400):
        d.ctrl[:] = 2 * np.pi * 2.0 * d.time + np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])
        mujoco.mj_step1(m, d)
        before = fast.depth > 0
        fast.compute(d)
        general.compute(d)
        left += int(np.count_nonzero(before & ~(fast.depth > 0)))
        entered += int(np.count_nonzero(~before & (fast.depth > 0)))
        buried = fast.depth > 0
        np.testing.assert_array_equal(fast.depth, general.depth)
        np.testing.assert_array_equal(fast.pos, general.pos)
        np.testing.assert_array_equal(fast.vel[buried], general.vel[buried])
        np.testing.assert_array_equal(fast.normal[buried], general.normal[buried])
        np.testing.assert_allclose(fast.force, general.force, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(fast.terrain_state.u, general.terrain_state.u, rtol=1e-12, atol=1e-18)
        np.testing.assert_allclose(fast.wrench, general.wrench, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(fast.terrain_state.stiff, general.terrain_state.stiff, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(fast.terrain_state.imp, general.terrain_state.imp, rtol=1e-10, atol=1e-12)
        springs += int(np.count_nonzero(fast.terrain_state.imp[:, 0] > 0))
        assert np.all(fast.force[~buried] == 0.0) and np.all(fast.terrain_state.u[~buried] == 0.0)
        d.xfrc_applied[rows] = fast.wrench[rows]
        mujoco.mj_step2(m, d)
        d.xfrc_applied[rows] = 0.0
    assert entered > 100 and left > 100  # the legs went in and came out many times
    if yield_displacement is None:  # bodies with elements below yield (the implicit step's springs) on many steps
        assert springs > 100


def test_flat_dry_pass_reports_nonfinite_position():
    from mjrft.models import hexapod_model
    m = hexapod_model()
    d = mujoco.MjData(m)
    t = mjrft.GranularTerrain(m, resolution=0.01)
    t.step(d, 50)
    mujoco.mj_step1(m, d)
    leg = m.body("leg_rf").id
    d.xpos[leg, 0] = np.inf  # a leg near the sand (not culled) with a corrupted position
    with pytest.raises(mjrft.NonFiniteError, match=r"non-finite state .* on body 'leg_rf'"):
        t.compute(d)


def test_group_inside_the_dry_strip_of_a_shoal_costs_and_gives_what_the_dry_scene_does():
    """Strips of saturated sand and water from x = 0.5 m change nothing for a robot walking in the
    dry strip before them: the same forces, memory and wrench as the one-region dry scene, on every
    step (its groups take the dry pass; those near the strip edge, within the blend, the general one)."""
    from mjrft.models import hexapod_model
    m = hexapod_model()
    d = mujoco.MjData(m)
    dry = mjrft.GranularTerrain(m, resolution=0.008)
    shoal = mjrft.GranularTerrain(m, resolution=0.008, buoyancy=True, regions=[
        mjrft.Region(0.5, "sea_sand_saturated", "wet"), mjrft.Region(1.0, "sea_sand_saturated", "wet", 0.02)])
    assert shoal.terrain_model.surface.top == pytest.approx(0.02)
    rows = dry.body_ids
    for k in range(300):
        d.ctrl[:] = 2 * np.pi * 2.0 * d.time + np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])
        mujoco.mj_step1(m, d)
        dry.compute(d)
        shoal.compute(d)
        np.testing.assert_array_equal(dry.force, shoal.force)
        np.testing.assert_array_equal(dry.terrain_state.u, shoal.terrain_state.u)
        np.testing.assert_array_equal(dry.wrench, shoal.wrench)
        assert np.all(shoal.region[shoal.depth > 0] == 0)
        d.xfrc_applied[rows] = dry.wrench[rows]
        mujoco.mj_step2(m, d)
        d.xfrc_applied[rows] = 0.0
    assert 0.0 < d.qpos[0] < 0.4  # it walked, inside the dry strip
