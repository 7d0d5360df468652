"""Regions (strips along x, a region map), the height-field free surface, the MJCF <custom> set-up, malformed
input, and the shoal scene and environment."""

import math
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft import laws
from mjrft.regions import Region, RegionMap
from mjrft.params import P_WATER_DRAG

SAND = "sea_sand_saturated"
DT = 1e-3

BOX = """<mujoco><compiler angle="radian"/><option timestep="0.001"/>{asset}<worldbody>{ground}
<body name="b" pos="0 0 0.3"><freejoint/><geom name="g" type="box" size="{size}" mass="0.1"/></body>
</worldbody>{custom}</mujoco>"""

HFIELD = """<asset><hfield name="hf" nrow="{nrow}" ncol="{ncol}" size="{size}" elevation="{elev}"/></asset>"""


def model(size=(0.15, 0.04, 0.01), asset="", ground="", custom=""):
    m = mujoco.MjModel.from_xml_string(BOX.format(size=" ".join(map(str, size)), asset=asset, ground=ground,
                                                  custom=custom))
    return m, mujoco.MjData(m)


def place(m, d, pos, vel=(0, 0, 0), quat=(1, 0, 0, 0)):
    d.qpos[:3], d.qpos[3:7] = pos, quat
    d.qvel[:] = 0.0
    d.qvel[:3] = vel
    mujoco.mj_forward(m, d)


def pure(m, **kw):
    """A terrain without rest memory (yield_displacement 0, tiny v_eps): forces are the laws themselves (too
    stiff to step with; the tests that use it ignore the stability warning)."""
    return mjrft.GranularTerrain(m, geoms=["g"], yield_displacement=0.0, v_eps=1e-9, **kw)


stiff_ok = pytest.mark.filterwarnings("ignore::mjrft.TerrainStabilityWarning")


def expected_forces(t, weights):
    """Per element: the weighted sum over regions of each region's law, plus the water law where the region has
    water, evaluated directly (no coupler)."""
    f = np.zeros((t.n_elements, 3))
    for r, reg in enumerate(t.regions):
        w = weights[:, r]
        if np.any(w > 0):
            g = laws.apply_law(reg.law, t.depth, t.normal, t.vel, t.area, reg.medium)
            if reg.water_depth > 0:
                g += laws.water(t.depth, t.normal, t.vel, t.area, reg.medium.with_extra(water_depth=reg.water_depth))
            f += w[:, None] * g
    return f


# ---------------------------------------------------------------------------------------------- strips
@stiff_ok
def test_strips_evaluate_each_elements_region_and_blend_at_boundaries():
    m, d = model()
    regions = [(0.0, "glass3_cp", "depth_only"), Region(0.1, SAND, "wet")]
    t = pure(m, medium="poppy_cp", law="rft", resolution=0.008, regions=regions)
    assert [r.law for r in t.regions] == ["rft", "depth_only", "wet"] and t.regions[2].x_min == 0.1
    place(m, d, (0.02, 0.0, -0.005), (0.05, 0.01, -0.03))
    t.compute(d, DT)
    w = t.region_weights(t.pos[:, 0], t.pos[:, 1])
    below = t.depth > 0
    assert set(np.unique(t.region[below])) == {0, 1, 2}
    np.testing.assert_allclose(w.sum(axis=1), 1.0, rtol=1e-12)
    blended = below & (w.max(axis=1) < 1)
    assert blended.sum() >= 4  # elements within transition / 2 of x = 0 and x = 0.1
    np.testing.assert_array_equal(t.region[below], np.argmax(w[below], axis=1))
    np.testing.assert_allclose(t.force, expected_forces(t, w), rtol=1e-9, atol=1e-12)
    # the weights: linear over the 1 cm transition centred on each boundary
    np.testing.assert_allclose(t.region_weights([-0.006, -0.005, -0.0025, 0.0, 0.004, 0.096, 0.1, 0.2], 0.0),
                               [[1, 0, 0], [1, 0, 0], [0.75, 0.25, 0], [0.5, 0.5, 0], [0.1, 0.9, 0],
                                [0, 0.9, 0.1], [0, 0.5, 0.5], [0, 0, 1]], atol=1e-12)


@stiff_ok
def test_one_region_does_no_region_work_and_unused_laws_cost_nothing():
    m, d = model()
    t = pure(m, medium="poppy_cp", law="rft", resolution=0.01)
    assert t.terrain_model.regions.bounds.size == 0 and t.terrain_model.regions.map.size == 0 and len(t.regions) == 1
    place(m, d, (0.5, 0.3, -0.005), (0.05, 0.0, -0.02))
    t.compute(d, DT)
    assert np.all(t.region == 0)
    np.testing.assert_allclose(t.force, laws.rft(t.depth, t.normal, t.vel, t.area, "poppy_cp"), rtol=1e-9,
                               atol=1e-12)


# ---------------------------------------------------------------------------------------------- region map
@stiff_ok
def test_region_map_cells_and_bilinear_blend():
    m, d = model(size=(0.05, 0.05, 0.01))
    ids = np.array([[0, 1, 1],
                    [2, 3, 0]])  # rows along y (cells 5 cm), columns along x
    regions = [(SAND, "wet"), ("glass3_cp", "rft3d"), ("poppy_lp", "depth_only", 0.01)]
    t = pure(m, medium="poppy_cp", law="rft", resolution=0.01, regions=regions,
             region_map=RegionMap(ids, x_min=0.0, y_min=0.0, cell=0.05), transition=0.05)
    assert t.regions[3].water_depth == 0.01 and t.terrain_model.regions.map.shape == (2, 3)
    rw = t.region_weights
    centres = rw([0.025, 0.075, 0.125, 0.025, 0.075, 0.125], [0.025, 0.025, 0.025, 0.075, 0.075, 0.075])
    np.testing.assert_allclose(centres, np.eye(4)[ids.ravel()], atol=1e-12)
    np.testing.assert_allclose(rw(0.05, 0.025), [0.5, 0.5, 0, 0], atol=1e-12)  # edge between ids 0 and 1
    np.testing.assert_allclose(rw(0.05, 0.05), [0.25, 0.25, 0.25, 0.25], atol=1e-12)  # corner of four
    np.testing.assert_allclose(rw(0.1, 0.05), [0.25, 0.5, 0, 0.25], atol=1e-12)  # 1, 1 / 3, 0
    np.testing.assert_allclose(rw(-1.0, 5.0), [0, 0, 1, 0], atol=1e-12)  # outside: the border cells continue
    # a narrower transition leaves each cell pure except within transition / 2 of its edges
    t2 = pure(m, medium="poppy_cp", law="rft", resolution=0.01, regions=regions,
              region_map=RegionMap(ids, x_min=0.0, y_min=0.0, cell=(0.05, 0.05)), transition=0.01)
    np.testing.assert_allclose(t2.region_weights([0.044, 0.048, 0.05], 0.025), [[1, 0, 0, 0], [0.7, 0.3, 0, 0],
                                                                              [0.5, 0.5, 0, 0]], atol=1e-12)
    # elements: forces are the weighted laws of their regions (the box straddles the map's centre)
    place(m, d, (0.06, 0.05, -0.004), (0.04, -0.02, -0.03))
    t.compute(d, DT)
    w = t.region_weights(t.pos[:, 0], t.pos[:, 1])
    assert len(set(np.unique(t.region[t.depth > 0]))) >= 3
    assert np.any(t.force[(t.depth < 0) & (w[:, 3] > 0)] != 0)  # the water over region 3
    np.testing.assert_allclose(t.force, expected_forces(t, w), rtol=1e-9, atol=1e-12)
    # with the narrow transition most elements lie inside one cell (looked up inline, no blending)
    place(m, d, (0.06, 0.05, -0.004), (0.04, -0.02, -0.03))
    t2.compute(d, DT)
    w2 = t2.region_weights(t2.pos[:, 0], t2.pos[:, 1])
    below = t2.depth > 0
    assert (w2[below].max(axis=1) == 1).sum() > 0.5 * below.sum() and (w2[below].max(axis=1) < 1).sum() >= 4
    np.testing.assert_array_equal(t2.region[below], np.argmax(w2[below], axis=1))
    np.testing.assert_allclose(t2.force, expected_forces(t2, w2), rtol=1e-9, atol=1e-12)
    # continuity: along a path the weights change by at most v dt / transition per axis per step
    xs = np.arange(0.0, 0.15, 1e-4)
    wp = rw(xs, 0.03 + 0.2 * xs)
    assert np.max(np.abs(np.diff(wp, axis=0))) <= 2 * 1e-4 / 0.05 + 1e-12


# ---------------------------------------------------------------------------------------------- height field
ELEV = "0.8 0.9 1.0 0.0  0.4 0.5 0.6 0.7  0 0.1 0.2 0.3"


def hfield_model(yaw=0.0, custom=""):
    asset = HFIELD.format(nrow=3, ncol=4, size="0.3 0.2 0.05 0.1", elev=ELEV)
    ground = (f'<geom name="ground" type="hfield" hfield="hf" pos="0.1 -0.05 0.01" euler="0 0 {yaw}" '
              'contype="0" conaffinity="0"/><geom name="post" type="box" size=".01 .01 .01" pos="1 1 1"/>')
    return model(size=(0.03, 0.02, 0.004), asset=asset, ground=ground, custom=custom)


@pytest.mark.parametrize("yaw", [0.0, 0.6])
def test_height_field_surface_is_bilinear_between_mujocos_samples(yaw):
    m, d = hfield_model(yaw)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", surface="ground", geoms=["g"], resolution=0.01)
    assert t.surface_hfield == 0
    mujoco.mj_forward(m, d)
    R, o = d.geom_xmat[0].reshape(3, 3), d.geom_xpos[0]
    h = m.hfield_data.reshape(3, 4) * 0.05 + 0.01
    assert t.surface == pytest.approx(h.mean())
    geomid = np.zeros(1, np.int32)
    for r in range(3):
        for c in range(4):
            local = np.clip([-0.3 + 0.2 * c, -0.2 + 0.2 * r, 0.0], [-0.29999, -0.19999, 0], [0.29999, 0.19999, 0])
            p = o + R @ local
            ray = mujoco.mj_ray(m, d, p + [0, 0, 1.0], np.array([0, 0, -1.0]), None, 1, -1, geomid)
            z = float(t.surface_height(p[0], p[1]))
            assert z == pytest.approx(p[2] + 1.0 - ray, abs=5e-6)  # MuJoCo's own surface at its samples
            assert z == pytest.approx(h[r, c], abs=5e-6)
    # bilinear in the cell between samples: the centre of a cell is the mean of its corners
    centre = o + R @ [-0.3 + 0.2 * 1.5, -0.2 + 0.2 * 0.5, 0]
    assert float(t.surface_height(centre[0], centre[1])) == pytest.approx(h[0:2, 1:3].mean(), rel=1e-12)
    # along an edge, linear; outside the field the border heights continue
    q = o + R @ [-0.3 + 0.2 * 2.25, -0.2, 0]
    assert float(t.surface_height(q[0], q[1])) == pytest.approx(0.75 * h[0, 2] + 0.25 * h[0, 3], rel=1e-12)
    far = o + R @ [-0.3 - 1.0, -0.2 - 1.0, 0]
    assert float(t.surface_height(far[0], far[1])) == pytest.approx(h[0, 0], rel=1e-12)
    # every element's depth is the local surface height minus its height
    place(m, d, (o[0], o[1], float(t.surface_height(o[0], o[1]))), (0.01, 0, -0.01))
    t.compute(d, DT)
    on = t.depth != 0
    assert on.sum() > 10
    np.testing.assert_allclose(t.depth[on], t.surface_height(t.pos[on, 0], t.pos[on, 1]) - t.pos[on, 2],
                               rtol=1e-12, atol=1e-15)
    assert np.any(t.depth > 0) and np.any(t.depth < 0)


@stiff_ok
def test_element_moving_along_a_height_field_slope():
    """A plate sliding up a planar slope at a constant (vertical) depth feels a constant force, the law's."""
    slope = 0.1
    asset = HFIELD.format(nrow=2, ncol=2, size="0.5 0.5 0.1 0.1", elev="0 1 0 1")  # z = 0.05 + 0.1 x
    ground = '<geom name="slope" type="hfield" hfield="hf" contype="0" conaffinity="0"/>'
    m, d = model(size=(0.02, 0.02, 0.002), asset=asset, ground=ground)
    t = pure(m, medium="poppy_cp", law="rft", surface="slope", resolution=0.005)
    np.testing.assert_allclose(t.surface_height([-0.2, 0.0, 0.3], 0.1), 0.05 + slope * np.array([-0.2, 0, 0.3]),
                               rtol=1e-12)
    v = np.array([0.05, 0.0, 0.05 * slope])  # along the slope
    quat = (math.cos(math.atan(slope) / 2), 0, -math.sin(math.atan(slope) / 2), 0)  # plate parallel to it
    forces = []
    for k in range(200):
        x = -0.1 + k * DT * v[0]
        place(m, d, (x, 0.0, 0.05 + slope * x - 0.01), v, quat)
        t.compute(d, DT)
        forces.append(t.wrench[1, :3].copy())
    forces = np.array(forces)
    assert np.linalg.norm(forces[0]) > 0.05
    np.testing.assert_allclose(forces, np.broadcast_to(forces[0], forces.shape), rtol=1e-9, atol=1e-12)
    # and that force is the law with depth measured vertically from the slope (computed here independently)
    depth = 0.05 + slope * t.pos[:, 0] - t.pos[:, 2]
    f = laws.rft(np.maximum(depth, 0.0), t.normal, t.vel, t.area, "poppy_cp")
    np.testing.assert_allclose(forces[-1], f.sum(axis=0), rtol=1e-9, atol=1e-12)


# ---------------------------------------------------------------------------------------------- MJCF <custom>
def test_custom_section_carries_regions_map_water_and_hfield():
    custom = """<custom>
      <text name="mjrft:medium" data="poppy_cp"/><text name="mjrft:law" data="rft"/><text name="mjrft:geoms" data="g"/>
      <text name="mjrft:surface_hfield" data="ground"/>
      <text name="mjrft:regions" data="sea_sand_saturated wet 0.02; glass3_cp depth_only"/>
      <numeric name="mjrft:region_map" data="-0.1 -0.2 0.1 0.2 2 2  0 1 2 1"/>
      <numeric name="mjrft:transition" data="0.02"/><numeric name="mjrft:buoyancy" data="1"/>
      <numeric name="mjrft:water_depth" data="0.005"/><numeric name="mjrft:drag_coefficient" data="1.0"/>
      <numeric name="mjrft:water_density" data="1025"/>
    </custom>"""
    m, _ = hfield_model(custom=custom)
    t = mjrft.GranularTerrain(m)
    kw = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], surface="ground",
                               regions=[(SAND, "wet", 0.02), Region(None, "glass3_cp", "depth_only")],
                               region_map=RegionMap(np.array([[0, 1], [2, 1]]), -0.1, -0.2, (0.1, 0.2)),
                               transition=0.02, buoyancy=True, water_depth=0.005, drag_coefficient=1.0,
                               water_density=1025.0)
    assert t.surface_hfield == kw.surface_hfield == 0 and t.buoyancy and t.transition == 0.02
    for group, a in (("regions", "law"), ("regions", "params"), ("regions", "rho"), ("regions", "map"),
                     ("regions", "map_frame"), ("surface", "hfield_z"), ("surface", "hfield_frame")):
        np.testing.assert_array_equal(getattr(getattr(t.terrain_model, group), a),
                                      getattr(getattr(kw.terrain_model, group), a), err_msg=a)
    assert [r.water_depth for r in t.regions] == [0.005, 0.02, 0.0]
    assert t.terrain_model.regions.params[1, P_WATER_DRAG] == 1025.0
    assert t.terrain_model.regions.rho.tolist() == [1025.0, 1025.0, 0.0]  # water, wet sand under water; dry glass: none
    # strips from <custom> text, keyword arguments override the file
    m2, _ = model(custom='<custom><text name="mjrft:regions" data="0.1 glass3_cp rft3d; 0.3 sea_sand_saturated '
                         'wet 0.01"/></custom>')
    t2 = mjrft.GranularTerrain(m2)
    assert t2.terrain_model.regions.bounds.tolist() == [0.1, 0.3]
    assert [r.law for r in t2.regions] == ["rft", "rft3d", "wet"]
    assert mjrft.GranularTerrain(m2, regions=[]).regions[0].law == "rft" and \
        len(mjrft.GranularTerrain(m2, regions=[]).regions) == 1


# ---------------------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("kw,err,msg", [
    (dict(regions=[(0.1, "poppy_cp", "rft"), (0.0, "poppy_cp", "rft")]), ValueError, "sorted by increasing x_min"),
    (dict(regions=[(0.0, "poppy_cp", "rft"), (0.5, "mud", "rft")]), mjrft.UnknownNameError,
     "unknown region 2 medium 'mud'; valid choices: .*poppy_cp"),
    (dict(regions=[(0.0, "poppy_cp", "fancy")]), mjrft.UnknownNameError,
     "unknown region 1 law 'fancy'; valid choices: depth_only, .*water, wet"),
    (dict(regions=[(0.0, "poppy_cp", "rft", -0.01)]), ValueError, "region 1 water_depth must be finite and >= 0"),
    (dict(water_depth=-1.0), ValueError, "^water_depth must be finite and >= 0, got -1.0"),
    (dict(regions=[(0.0, "poppy_cp", "rft", math.nan)]), ValueError, "region 1 water_depth must be finite"),
    (dict(regions=[(math.inf, "poppy_cp", "rft")]), ValueError, "region 1 x_min must be finite"),
    (dict(regions=[(0.0, "poppy_cp", "rft"), (0.005, "poppy_cp", "rft")]), ValueError,
     "region 1 is 0.005 m wide .* less than the transition width 0.01 m"),
    (dict(regions=[("poppy_cp", "rft")]), ValueError, r"region 1: expected \(x_min, medium, law\[, water_depth\]\)"),
    (dict(regions="0.1 poppy_cp"), ValueError, "region 1: expected"),
    (dict(regions=[Region(None, "poppy_cp", "rft")]), ValueError, "region 1: strips along x need x_min"),
    (dict(transition=-0.01), ValueError, "transition must be finite and >= 0"),
    (dict(drag_coefficient=math.inf), ValueError, "drag_coefficient must be finite"),
    (dict(surface="nowhere"), mjrft.UnknownNameError,
     "surface 'nowhere' is neither a number nor a geom of the model; hfield geoms: ground"),
    (dict(surface="post"), ValueError, "surface geom 'post' has type mjGEOM_BOX, not an hfield; hfield geoms: ground"),
    (dict(regions=[(0.0, "poppy_cp", "rft")], region_map=RegionMap(np.zeros((2, 2)), 0, 0, 0.05)), ValueError,
     "regions used by a region_map take no x_min"),
    (dict(regions=[("poppy_cp", "rft")], region_map=RegionMap(np.array([[0, 2]]), 0, 0, 0.05)), ValueError,
     "region_map id 2 at row 0, column 1 is not a region: valid ids 0..1"),
    (dict(regions=[("poppy_cp", "rft")], region_map=RegionMap(np.array([[0, 1]]), 0, 0, 0.005)), ValueError,
     "transition width 0.01 m exceeds the region_map cell 0.005 m"),
    (dict(region_map=RegionMap(np.array([0, 0]), 0, 0, 0.05)), ValueError, "non-empty 2D array"),
    (dict(region_map=RegionMap(np.array([[0.5]]), 0, 0, 0.05)), ValueError, "region_map ids must be integers"),
    (dict(region_map=RegionMap(np.array([[0]]), 0, 0, -1.0)), ValueError, "region_map cell_x must be finite and > 0"),
])
def test_malformed_input_raises_named_errors(kw, err, msg):
    m, _ = hfield_model()
    with pytest.raises(err, match=msg):
        mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], **kw)


def test_unsupported_height_fields_are_rejected():
    asset = HFIELD.format(nrow=2, ncol=2, size="0.5 0.5 0.1 0.1", elev="0 1 0 1")
    tilted = '<geom name="ground" type="hfield" hfield="hf" euler="0.2 0 0" contype="0" conaffinity="0"/>'
    m, _ = model(asset=asset, ground=tilted)
    with pytest.raises(ValueError, match="surface hfield geom 'ground' is tilted"):
        mjrft.GranularTerrain(m, surface="ground", geoms=["g"])
    moving = ('<body name="raft" pos="0 0 0"><freejoint/><geom name="ground" type="hfield" hfield="hf" '
              'contype="0" conaffinity="0"/><geom type="sphere" size="0.1"/></body>')
    m, _ = model(asset=asset, ground=moving)
    with pytest.raises(ValueError, match="surface hfield geom 'ground' is on a moving body"):
        mjrft.GranularTerrain(m, surface="ground", geoms=["g"])
    m, _ = model(custom='<custom><numeric name="mjrft:region_map" data="0 0 0.1 0.1 2 2 0 0"/></custom>')
    with pytest.raises(ValueError, match="nx x ny ids, got 2 ids"):
        mjrft.GranularTerrain(m, geoms=["g"])


# ---------------------------------------------------------------------------------------------- the shoal
def test_shoal_model_carries_its_terrain():
    from mjrft.models import hexapod_shoal_model, model_path
    from mjrft.models.generate import generated

    assert open(model_path("hexapod_shoal")).read() == generated("hexapod_shoal")
    m = mujoco.MjModel.from_xml_path(model_path("hexapod_shoal"))
    t = mjrft.GranularTerrain(m)
    assert [(r.x_min, r.medium.name, r.law, r.water_depth) for r in t.regions] == [
        (None, "poppy_cp", "rft", 0.0), (0.5, SAND, "wet", 0.0), (1.0, SAND, "wet", 0.02)]
    assert t.buoyancy and t.transition == 0.01 and t.water_depth == 0.02
    assert m.geom("water_2").size[2] == pytest.approx(0.01)  # the visual water layer, 2 cm deep
    assert hexapod_shoal_model(regions=[]).ntext < m.ntext


def test_shoal_env_checks_and_walks_into_the_water():
    gymnasium = pytest.importorskip("gymnasium")
    pytest.importorskip("imageio")
    from gymnasium.utils.env_checker import check_env

    import mjrft.envs  # noqa: F401

    env = gymnasium.make("mjrft/HexapodShoal-v0", max_episode_steps=60)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check_env(env.unwrapped, skip_render_check=True)
    env.reset(seed=0)
    u = env.unwrapped
    u.data.qpos[0] = 0.95  # just before the water (x >= 1)
    mujoco.mj_forward(u.model, u.data)
    seen, wet_force = set(), 0.0
    a = np.full(6, 2 * np.pi * 2.0 / u.task.max_hip_speed, dtype=np.float32)  # tripod at 2 Hz, legs half a turn apart
    u.target[list(u.TRIPOD_B_IDX)] += np.pi
    for _ in range(60):
        obs, reward, terminated, truncated, info = env.step(a)
        assert np.isfinite(obs).all() and np.isfinite(reward)
        t = u.terrain
        seen |= set(np.unique(t.region[t.depth > -0.02]).tolist())
        in_water = (t.depth < 0) & (t.region == 2)
        wet_force = max(wet_force, float(np.abs(t.force[in_water]).sum()))
        if terminated or truncated:
            break
    assert u.data.qpos[0] > 1.0 and 2 in seen
    assert wet_force > 0  # legs in the water feel its drag and buoyancy
    env.close()
