"""The surface elements of the selected geoms (mjrft.elements): cull groups compact in space, so that the
kernel skips the groups above the sand, and the element budget checked before any element is built."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import mjrft


LYING_CAPSULE = """<mujoco><worldbody><body name="foot" pos="0 0 0.04"><freejoint/>
<geom name="foot" type="capsule" fromto="-0.2 0 0 0.2 0 0" size="0.06"/></body></worldbody></mujoco>"""


def test_compact_order_makes_runs_the_leaves_of_a_kd_split():
    from mjrft.elements import compact_order
    rng = np.random.default_rng(0)
    pts = rng.uniform(size=(200, 3)) * [1.0, 0.1, 0.01]
    order = compact_order(pts, size=32)
    assert sorted(order) == list(range(200))
    # the longest side (x) is split first, at 4 runs of 32: the first 128 points are the 128 smallest x
    np.testing.assert_array_equal(np.sort(order[:128]), np.sort(np.argsort(pts[:, 0])[:128]))
    runs = [pts[order[a:a + 32]] for a in range(0, 200, 32)]
    assert max(np.ptp(r[:, 0]) for r in runs) < 0.3  # compact along x; in the given order a run spans all of it
    assert max(np.ptp(pts[a:a + 32, 0]) for a in range(0, 200, 32)) > 0.8


def test_cull_runs_are_compact_so_a_lying_capsule_works_near_its_bottom_only():
    """A capsule lying 2 cm deep (a Hopper's foot): only the cull groups near its bottom are within reach. The
    control, the same elements in runs of the discretisation's own order (rings around the axis, each reaching from
    the bottom to the top), has far more elements within reach."""
    from mjrft.elements import CULL_GROUP, _cull_groups
    from mjrft.geometry import discretize_geom, exposed_elements
    m = mujoco.MjModel.from_xml_string(LYING_CAPSULE)
    d = mujoco.MjData(m)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01, floor=None, surface=0.0)
    mujoco.mj_forward(m, d)
    t.compute(d, 0.0)
    active = int(np.repeat(t.terrain_state.group_active, np.diff(t.terrain_model.elements.group_start)).sum())
    buried = int(np.count_nonzero(t.depth > 0))
    assert buried > 50 and active < 3 * buried < t.n_elements

    def within_reach(groups):
        g_geom, _, g_start, g_aabb = _cull_groups(m, groups)
        n = 0
        for g, gid in enumerate(g_geom):
            G = d.geom_xmat[gid]
            low = d.geom_xpos[gid, 2] + G[6:9] @ g_aabb[g, :3] - np.abs(G[6:9]) @ g_aabb[g, 3:]
            n += int(g_start[g + 1] - g_start[g]) if low < t.terrain_model.surface.top else 0
        return n

    gid = int(t.geom_ids[0])
    plain = exposed_elements(m, [gid], [discretize_geom(m, gid, 0.01)], 0.01)[0]
    assert len(plain) == t.n_elements and t.n_elements > 10 * CULL_GROUP
    assert within_reach([(gid, t.elements)]) == active  # the kernel culls what the boxes say
    assert within_reach([(gid, plain)]) > 1.8 * active


def test_a_resolution_that_would_build_too_many_elements_is_refused_up_front():
    import time

    from mjrft.geometry import estimate_elements
    from mjrft.models import hexapod_model

    m = hexapod_model()
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"resolution 1e-05 m would cut the \d+ selected geoms into about "
                                         r"[\d,]+ elements, more than max_elements = 1,000,000 .* coarser resolution"):
        mjrft.GranularTerrain(m, resolution=1e-5)
    assert time.perf_counter() - t0 < 5
    t = mjrft.GranularTerrain(m, resolution=0.01)
    est = estimate_elements(m, t.geom_ids, 0.01)
    assert 0.5 * t.n_elements < est < 3 * t.n_elements  # an estimate of the right size (before clipping)
    with pytest.raises(ValueError, match="max_elements = 10 "):
        mjrft.GranularTerrain(m, resolution=0.01, max_elements=10)
    assert mjrft.GranularTerrain(m, resolution=0.01, max_elements=est).n_elements == t.n_elements
    with pytest.raises(ValueError, match="max_elements must be finite and > 0"):
        mjrft.GranularTerrain(m, max_elements=0)
