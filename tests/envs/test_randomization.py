"""Terrain randomisation: the coupler's in-place terrain changes (set_medium, set_regions, set_surface) against
freshly built terrains, and the environments' ``terrain_randomization`` option (draws, seeding, info, vector env,
bad options)."""

import math
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.batch import BatchedTerrain
from mjrft.regions import Region
from mjrft.models import hexapod_xml

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it (gymnasium[mujoco])

from gymnasium.utils.env_checker import data_equivalence  # noqa: E402

from mjrft.envs import make_vector  # noqa: E402
from mjrft.envs.randomization import TerrainRandomization, rough_field  # noqa: E402

HEX = "mjrft/HexapodSand-v0"
SAND = "sea_sand_saturated"
DT = 1e-3
ALL = {"media": ["poppy_cp", "poppy_lp", "glass3_cp"], "stress_scale": [0.7, 1.3], "surface_height": [-0.005, 0.01],
       "roughness": 0.003, "strips": [0, 3]}

BOX = """<mujoco><option timestep="{dt}"/>{asset}<worldbody>{ground}
<body name="b" pos="0 0 0.3"><freejoint/><geom name="g" type="box" size="0.15 0.04 0.01" mass="{mass}"/></body>
</worldbody></mujoco>"""
HFIELD = '<asset><hfield name="hf" nrow="3" ncol="4" size="0.3 0.2 0.05 0.1"/></asset>'
HFIELD_GEOM = '<geom name="ground" type="hfield" hfield="hf" pos="0.1 -0.05 0.01" euler="0 0 0.6" contype="0" conaffinity="0"/>'


def box(hfield=False, mass=0.1, dt=DT):
    m = mujoco.MjModel.from_xml_string(BOX.format(dt=dt, mass=mass, asset=HFIELD if hfield else "",
                                                  ground=HFIELD_GEOM if hfield else ""))
    return m, mujoco.MjData(m)


def place(m, d, z=0.0, vel=(0.05, 0.0, -0.1)):
    d.qpos[:3], d.qpos[3:7] = (0.02, 0.0, z), (1, 0, 0, 0)
    d.qvel[:] = 0.0
    d.qvel[:3] = vel
    mujoco.mj_forward(m, d)


def forces(t, d):
    """The terrain's element forces and wrench from a clean memory at ``d``'s state."""
    t.reset()
    t.compute(d, DT)
    return t.force.copy(), t.wrench.copy()


def same(a, b, rtol=1e-12):
    """Equal to round-off (sums of many element forces: relative to the largest entry)."""
    for x, y in zip(a, b):
        np.testing.assert_allclose(x, y, rtol=rtol, atol=rtol * max(np.abs(y).max(), 1e-300))


# ---------------------------------------------------------------------------------------------- coupler
@pytest.mark.parametrize("law, medium, inertial", [
    ("rft", "poppy_cp", True), ("rft3d", "glass3_cp", True), ("depth_only", "poppy_lp", True), ("hybrid", "poppy_cp", False),
    ("wet", SAND, False)])
def test_stress_scale_multiplies_the_force_of_every_law(law, medium, inertial):
    """stress_scale 2 doubles every buried element's force, the inertial regime's included (0.5 m/s down is
    above poppy seeds' and 3 mm glass's critical speed)."""
    m, d = box()
    place(m, d, vel=(0.05, 0.0, -0.5))
    t = mjrft.GranularTerrain(m, medium, law, geoms=["g"], resolution=0.01, inertial=inertial or None)
    f1, w1 = forces(t, d)
    assert np.abs(f1).max() > 0
    if inertial:  # the inertial regime contributes here, so its slot is scaled too
        plain = mjrft.GranularTerrain(m, medium, law, geoms=["g"], resolution=0.01)
        assert np.abs(forces(plain, d)[0] - f1).max() > 1e-3 * np.abs(f1).max()
    t.set_medium(stress_scale=2.0)
    assert t.stress_scale == 2.0
    same(forces(t, d), (2 * f1, 2 * w1))
    t.set_medium(stress_scale=1.0)  # relative to the medium's own stresses, not to the last scale
    same(forces(t, d), (f1, w1))


def test_set_medium_equals_a_fresh_terrain_and_keeps_the_scale():
    m, d = box()
    place(m, d)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01)
    t.set_medium("glass03_lp", stress_scale=1.5)
    fresh = mjrft.GranularTerrain(m, "glass03_lp", "rft", geoms=["g"], resolution=0.01)
    assert t.medium.name == "glass03_lp" and t.stress_scale == 1.5
    f, w = forces(fresh, d)
    same(forces(t, d), (1.5 * f, 1.5 * w))
    t.set_medium("poppy_lp")  # the scale stays
    f, w = forces(mjrft.GranularTerrain(m, "poppy_lp", "rft", geoms=["g"], resolution=0.01), d)
    same(forces(t, d), (1.5 * f, 1.5 * w))


def test_set_regions_equals_a_fresh_terrain():
    m, d = box()
    place(m, d, z=0.005)
    regions = [Region(0.0, "glass3_cp", "rft"), Region(0.08, SAND, "wet", 0.01)]
    kw = dict(geoms=["g"], resolution=0.01, buoyancy=True)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", **kw)
    arrays = (t.terrain_model.regions.params, t.terrain_model.regions.law)
    t.set_regions(regions)
    fresh = mjrft.GranularTerrain(m, "poppy_cp", "rft", regions=regions, **kw)
    assert [(r.x_min, r.medium.name, r.law, r.water_depth) for r in t.regions] == \
           [(r.x_min, r.medium.name, r.law, r.water_depth) for r in fresh.regions]
    assert t.water_depth == fresh.water_depth == 0.01 and t.terrain_model.surface.top == fresh.terrain_model.surface.top
    same(forces(t, d), forces(fresh, d))
    assert set(np.unique(t.region[t.depth > 0])) == {0, 1, 2}
    t.set_regions([(0.05, "poppy_lp", "rft"), (0.1, SAND, "wet")])  # as many regions: the same arrays, refilled
    same(forces(t, d), forces(mjrft.GranularTerrain(m, "poppy_cp", "rft", regions=[(0.05, "poppy_lp", "rft"),
                                                                                  (0.1, SAND, "wet")], **kw), d))
    t.set_regions(None)  # back to one region: the old region ids are gone
    assert t.region.max() == 0 and len(t.regions) == 1 and t.water_depth == 0.0
    same(forces(t, d), forces(mjrft.GranularTerrain(m, "poppy_cp", "rft", **kw), d))
    assert t.terrain_model.regions.law.shape == arrays[1].shape == (1,)


def test_set_surface_flat_and_height_field():
    m, d = box()
    place(m, d, z=0.012)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01)
    assert np.abs(forces(t, d)[0]).max() == 0  # above the surface
    t.set_surface(0.015)
    assert t.surface == 0.015 and t.terrain_model.surface.top == 0.015
    same(forces(t, d), forces(mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01, surface=0.015), d))

    m, d = box(hfield=True)
    place(m, d, z=0.012)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01, surface="ground")
    x, y, z = t.surface_samples()
    assert x.shape == y.shape == z.shape == (3, 4)
    np.testing.assert_allclose(t.surface_height(x, y), z, rtol=0, atol=1e-15)  # the samples, in the yawed frame
    new = 0.01 + 0.004 * np.arange(12.0).reshape(3, 4) / 11
    t.set_surface(new)
    np.testing.assert_allclose(t.surface_samples()[2], new, rtol=0, atol=0)
    assert t.surface == pytest.approx(new.mean()) and t.terrain_model.surface.top == new.max()
    np.testing.assert_allclose(t.surface_height(x, y), new, rtol=0, atol=1e-15)
    # the model's hfield was rewritten: a terrain built on it now has the same surface (float32 samples)
    fresh = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01, surface="ground")
    np.testing.assert_allclose(fresh.surface_samples()[2], new, rtol=0, atol=1e-9)
    f, w = forces(fresh, d)
    assert np.abs(f).max() > 0
    same(forces(t, d), (f, w), rtol=1e-5)
    t.set_surface(0.02)  # one number: a level field
    np.testing.assert_array_equal(t.surface_samples()[2], 0.02)


def test_in_place_changes_refuse_bad_input_and_leave_the_terrain_as_it_was():
    m, d = box()
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01)
    with pytest.raises(mjrft.UnknownNameError, match="unknown medium 'mud'; valid choices: .*poppy_cp"):
        t.set_medium("mud")
    for bad in (0.0, -1.0, math.nan, math.inf, "x"):
        with pytest.raises(ValueError, match="stress_scale must be"):
            t.set_medium(stress_scale=bad)
    with pytest.raises(ValueError, match="sorted by increasing x_min"):
        t.set_regions([(0.5, "poppy_lp", "rft"), (0.1, "poppy_lp", "rft")])
    with pytest.raises(ValueError, match="surface is flat .* got an array of shape \\(2, 2\\)"):
        t.set_surface(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="surface must be finite"):
        t.set_surface(math.nan)
    with pytest.raises(ValueError, match="surface is flat"):
        t.surface_samples()
    assert (t.medium.name, t.stress_scale, len(t.regions), t.surface) == ("poppy_cp", 1.0, 1, 0.0)
    m, d = box(hfield=True)
    t = mjrft.GranularTerrain(m, geoms=["g"], resolution=0.01, surface="ground")
    with pytest.raises(ValueError, match=r"height field's shape \(3, 4\) \(nrow, ncol\), got \(4, 3\)"):
        t.set_surface(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="heights must be finite"):
        t.set_surface(np.full((3, 4), np.nan))


def test_stability_check_sees_the_scaled_stiffness():
    m, d = box(mass=2.0)
    place(m, d, z=0.0, vel=(0.0, 0.0, -0.01))
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01)
    forces(t, d)
    stiff = t.terrain_state.stiff.copy()
    t.set_medium(stress_scale=3.0)
    forces(t, d)
    same([t.terrain_state.stiff], [3 * stiff])  # the stiffness grows with the scale
    # a 1 g plate at a 10 ms step is beyond the limit: the warning names the scale
    m, d = box(mass=0.001, dt=0.01)
    place(m, d, z=0.0, vel=(0, 0, 0))
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01, yield_displacement=1e-4)
    t.set_medium(stress_scale=3.0)
    with pytest.warns(mjrft.TerrainStabilityWarning, match=r"exceeds the stability limit.*scaled x3\b"):
        t.step(d, 100)


def test_batched_terrain_follows_in_place_changes():
    """A BatchedTerrain steps each environment's changed terrain exactly as the terrain alone does (the arrays
    refilled in place, or replaced when the region count changes)."""
    xml = hexapod_xml(surface_grid=0.02)
    pairs = []
    for _ in range(2):
        models = [mujoco.MjModel.from_xml_string(xml) for _ in range(2)]
        pairs.append(([mujoco.MjData(mm) for mm in models], [mjrft.GranularTerrain(mm) for mm in models]))
    (bd, bt), (rd, rt) = pairs
    batch = BatchedTerrain(bt, bd)
    rng = np.random.default_rng(0)
    shape = bt[0].surface_samples()[2].shape
    bumps = 0.004 * rng.standard_normal(shape)
    changes = [lambda t: t.set_medium("poppy_lp", 1.3), lambda t: t.set_regions([(0.02, "glass3_cp", "rft")]),
               lambda t: t.set_surface(t.surface_samples()[2] + bumps), lambda t: t.set_regions([])]
    for k in range(6):
        if 1 <= k <= len(changes):
            for t in (bt[k % 2], rt[k % 2]):
                changes[k - 1](t)
        ctrl = rng.uniform(-1, 1, size=(2, 6))
        for e in range(2):
            bd[e].ctrl[:] = rd[e].ctrl[:] = ctrl[e]
            rt[e].step(rd[e], 10)
        batch.step(10)
        for e in range(2):
            for x, y in ((bd[e].qpos, rd[e].qpos), (bd[e].qvel, rd[e].qvel), (bt[e].force, rt[e].force)):
                assert np.array_equal(x, y)
    assert any(t.contact_mask().any() for t in bt)


# ---------------------------------------------------------------------------------------------- options
def test_rough_field_has_the_asked_statistics():
    rng = np.random.default_rng(0)
    h = rough_field(rng, (300, 300), (0.01, 0.01), 0.003, 0.05)
    assert abs(h.mean()) < 1e-15 and math.sqrt(np.mean(h * h)) == pytest.approx(0.003, rel=1e-12)

    def corr(lag):
        return float(np.mean(h[:, :-lag] * h[:, lag:]) + np.mean(h[:-lag] * h[lag:])) / 2 / 0.003 ** 2

    assert corr(5) == pytest.approx(math.exp(-1), abs=0.08)  # at the correlation length: 1/e
    assert corr(1) == pytest.approx(math.exp(-0.04), abs=0.05) and abs(corr(20)) < 0.1
    assert np.array_equal(h, rough_field(np.random.default_rng(0), (300, 300), (0.01, 0.01), 0.003, 0.05))
    assert np.all(rough_field(rng, (3, 4), (0.01, 0.01), 0.0, 0.05) == 0)


def test_options_normalise_and_nothing_drawn_is_off():
    r = TerrainRandomization.from_value({"media": "poppy_lp", "stress_scale": 2, "strips": 1})
    assert (r.media, r.stress_scale, r.strips, r.surface_height) == (("poppy_lp",), (2.0, 2.0), (1, 1), None)
    assert TerrainRandomization.from_value(r) is r
    assert TerrainRandomization.from_value(None) is None
    assert TerrainRandomization.from_value({}) is None and TerrainRandomization.from_value({"strips": 0}) is None


@pytest.mark.parametrize("value, match", [
    ({"medium": ["poppy_cp"]}, r"unknown terrain_randomization option 'medium'; valid choices: .*media.*stress_scale"),
    ({"media": ["poppy_cp", "mud"]}, r"unknown terrain_randomization medium 'mud'; valid choices: .*glass3_cp"),
    ({"stress_scale": [1.3, 0.7]}, r"stress_scale must be \[low, high\] with low <= high"),
    ({"stress_scale": [0.0, 1.0]}, r"stress_scale must be finite and > 0, got 0.0"),
    ({"stress_scale": [1, 2, 3]}, r"stress_scale must be \[low, high\] or a number"),
    ({"surface_height": "high"}, r"surface_height must be \[low, high\] or a number, got 'high'"),
    ({"roughness": -0.001}, r"roughness must be finite and >= 0"),
    ({"roughness": 0.002, "correlation_length": 0}, r"correlation_length must be finite and > 0"),
    ({"strips": [2, 1], "media": ["poppy_cp"]}, r"strips must be \[min, max\] integers with 0 <= min <= max"),
    ({"strips": 2.5, "media": ["poppy_cp"]}, r"strips must be \[min, max\] integers"),
    ({"strips": [1, 2]}, r"strips need media"),
    ({"strips": 1, "media": ["poppy_cp"], "strip_length": [0.001, 0.1]},
     r"strips must be at least the terrain's transition width 0.01 m long"),
    ({"roughness": 0.002, "correlation_length": 0.01}, r"correlation_length 0.01 m is shorter than two samples"),
    ("fast", r"terrain_randomization must be None, a dict of options .* got str 'fast'"),
])
def test_bad_options_raise_when_the_env_is_made(value, match):
    with pytest.raises(ValueError, match=match):
        gymnasium.make(HEX, terrain_randomization=value)


def test_options_the_scene_cannot_carry_raise():
    with pytest.raises(ValueError, match="terrain_randomization needs a sand environment; HexapodRigid has rigid"):
        gymnasium.make("mjrft/HexapodRigid-v0", terrain_randomization={"stress_scale": [1, 2]})
    with pytest.raises(ValueError, match="roughness needs a height-field sand surface: pass surface_grid="):
        gymnasium.make("mjrft/BipedSand-v0", terrain_randomization={"roughness": 0.002})
    with pytest.raises(ValueError, match="media: inertial=True: .*grain"):  # the small hexapod's inertial regime
        gymnasium.make(HEX, variant="small", terrain_randomization={"media": ["poppy_cp", "generic"]})


# ---------------------------------------------------------------------------------------------- environments
def test_off_by_default_and_a_constant_draw_changes_nothing():
    plain = gymnasium.make(HEX)
    same_terrain = gymnasium.make(HEX, terrain_randomization={"media": ["poppy_cp"], "stress_scale": 1.0})
    assert plain.unwrapped.randomizer is None and same_terrain.unwrapped.randomizer is not None
    (o1, i1), (o2, i2) = plain.reset(seed=2), same_terrain.reset(seed=2)
    assert "terrain" not in i1 and i2["terrain"]["medium"] == "poppy_cp"
    assert np.array_equal(o1, o2)  # the draw comes after the start pose's noise
    for _ in range(5):
        a = np.full(6, 0.4, np.float32)
        (o1, r1, *_, i1), (o2, r2, *_, i2) = plain.step(a), same_terrain.step(a)
        assert np.array_equal(o1, o2) and r1 == r2 and "terrain" not in i1 and "terrain" in i2


def test_seeded_draws_reproduce_and_differ():
    env = gymnasium.make(HEX, terrain_randomization=ALL)
    runs = []
    for seed in (3, 3, 4):
        obs, info = env.reset(seed=seed)
        obs = [obs] + [env.step(np.full(6, 0.4, np.float32))[0] for _ in range(3)]
        runs.append((info["terrain"], env.unwrapped.terrain.surface_samples()[2], obs))
    (ia, za, oa), (ib, zb, ob), (ic, zc, _) = runs
    assert ia == ib and np.array_equal(za, zb) and all(np.array_equal(x, y) for x, y in zip(oa, ob))
    assert ia != ic and not np.array_equal(za, zc)
    draws = set()
    for seed in range(12):
        t = env.reset(seed=seed)[1]["terrain"]
        draws.add(t["medium"])
        assert 0.7 <= t["stress_scale"] <= 1.3 and -0.005 <= t["surface_height"] <= 0.01 and len(t["strips"]) <= 3
    assert draws == {"poppy_cp", "poppy_lp", "glass3_cp"}


def test_info_says_what_the_terrain_is():
    env = gymnasium.make(HEX, terrain_randomization=ALL)
    u = env.unwrapped
    _, info = env.reset(seed=1)
    t = info["terrain"]
    assert set(t) == {"medium", "stress_scale", "surface_height", "roughness", "strips"}
    assert t["medium"] == u.terrain.medium.name and t["stress_scale"] == u.terrain.stress_scale
    assert t["roughness"] == 0.003
    z = u.terrain.surface_samples()[2]
    assert z.shape == (101, 201)  # the 2 x 1 m bed at DEFAULT_SURFACE_GRID = 1 cm
    assert z.mean() == pytest.approx(t["surface_height"], abs=1e-12)
    assert math.sqrt(np.mean((z - z.mean()) ** 2)) == pytest.approx(0.003, rel=1e-9)
    assert t["strips"] == tuple((r.x_min, r.medium.name) for r in u.terrain.regions[1:])
    assert all(r.law == "rft" for r in u.terrain.regions)
    h = u.model.geom_dataid[u.terrain.surface_hfield]
    adr, elev = u.model.hfield_adr[h], u.model.hfield_size[h, 2]
    np.testing.assert_allclose(u.model.hfield_data[adr:adr + z.size] * elev, z.ravel(), atol=1e-9)  # rendered too
    step_info = env.step(np.zeros(6, np.float32))[4]
    assert step_info["terrain"] == t and step_info["terrain"] is not t


def test_a_raised_surface_buries_the_robot():
    """A 1 cm raise starts the legs 1 cm deep (the start pose does not move); the flat scene's visual sand moves
    with the surface."""
    flat = gymnasium.make(HEX, terrain_randomization={"media": ["poppy_cp"]})
    raised = gymnasium.make(HEX, terrain_randomization={"surface_height": 0.01})
    box_z = raised.unwrapped.model.geom_pos[raised.unwrapped.model.geom("sand_surface").id, 2]
    for env in (flat, raised):
        env.reset(seed=0)
    assert raised.unwrapped.terrain.surface == 0.01
    assert raised.unwrapped.model.geom_pos[raised.unwrapped.model.geom("sand_surface").id, 2] == box_z + 0.01
    a = np.zeros(6, np.float32)
    i_flat, i_raised = flat.step(a)[4], raised.step(a)[4]
    assert i_flat["sinkage"].max() < 1e-3 and i_raised["sinkage"].max() > 9e-3
    assert i_raised["granular_force"][:, 2].sum() > 10 * max(i_flat["granular_force"][:, 2].sum(), 1e-3)


def test_drawn_strips_replace_the_scenes():
    """On the shoal, drawn strips replace its saturated-sand and water strips (region 0 keeps its medium draw and
    law); their visual boxes are hidden and the first box covers the bed."""
    env = gymnasium.make("mjrft/HexapodShoal-v0", terrain_randomization={"media": ["poppy_lp"], "strips": 2,
                                                                          "strip_length": [0.3, 0.3]})
    t = env.reset(seed=0)[1]["terrain"]
    u = env.unwrapped
    assert t["strips"] == ((pytest.approx(0.3), "poppy_lp"), (pytest.approx(0.6), "poppy_lp"))
    assert [(r.medium.name, r.law, r.water_depth) for r in u.terrain.regions] == [("poppy_lp", "rft", 0.0)] * 3
    assert u.terrain.water_depth == 0.0
    m = u.model
    assert m.geom_rgba[m.geom("sand_1").id, 3] == m.geom_rgba[m.geom("water_2").id, 3] == 0.0
    first = m.geom("sand_surface").id
    assert (m.geom_pos[first, 0] - m.geom_size[first, 0], m.geom_pos[first, 0] + m.geom_size[first, 0]) == (-0.5, 2.5)


def test_vector_env_with_randomization_equals_the_single_envs(run_both):
    kw = dict(terrain_randomization=ALL, healthy_z_range=(0.0455, 0.5))
    ours = make_vector(HEX, 3, max_episode_steps=6, **kw)
    sync = gymnasium.make_vec(HEX, num_envs=3, vectorization_mode="sync", max_episode_steps=6, **kw)
    a, b = ours.reset(seed=4), sync.reset(seed=4)
    assert data_equivalence(a, b, exact=True)
    single = gymnasium.make(HEX, **kw)
    assert single.reset(seed=5)[1]["terrain"] == {k: v[1] for k, v in a[1]["terrain"].items() if not k.startswith("_")}
    ended = run_both(ours, sync, 14, seed=0, reset_seed=4)  # the same draws again, then 14 identical steps
    assert ended >= 3  # episodes ended and were reset with new terrains, in both alike
    ours.close()
    sync.close()


def test_command_line_value_reaches_the_env():
    from mjrft.train.train import parse_kwargs

    kw = parse_kwargs(['terrain_randomization={"media": ["poppy_cp", "poppy_lp"], "stress_scale": [0.7, 1.3]}'])
    assert kw == {"terrain_randomization": {"media": ["poppy_cp", "poppy_lp"], "stress_scale": [0.7, 1.3]}}
    env = gymnasium.make(HEX, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # gymnasium's checker: no shared info objects
        env.reset(seed=0)
        env.step(env.action_space.sample())
        env.step(env.action_space.sample())
    assert env.unwrapped.randomizer.options.media == ("poppy_cp", "poppy_lp")


RENDER_SCRIPT = """
import sys
import mujoco
try:
    mujoco.GLContext(8, 8).make_current()
except Exception as exc:
    print("NO-GL", type(exc).__name__, exc)
    sys.exit(0)
import gymnasium, numpy as np, mjrft
env = gymnasium.make("mjrft/HexapodSand-v0", render_mode="rgb_array", width=160, height=120, camera_name="track",
                     terrain_randomization={"roughness": 0.004, "correlation_length": 0.04})
imgs = []
for seed in (0, 1, 0):
    env.reset(seed=seed)
    imgs.append(env.render().astype(float))
print("DIFF", np.abs(imgs[0] - imgs[1]).mean(), np.abs(imgs[0] - imgs[2]).max())
"""


def test_the_rendered_height_field_follows_each_draw():
    """Off-screen (EGL, in a subprocess as in test_envs): after each reset the render context gets the new heights,
    so seed 0, seed 1, seed 0 again render the first frame again, and seed 1 another."""
    import os
    import subprocess
    import sys
    env = dict(os.environ, MUJOCO_GL="egl", PYOPENGL_PLATFORM="egl")
    out = subprocess.run([sys.executable, "-c", RENDER_SCRIPT], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    if "NO-GL" in out.stdout:
        pytest.skip(f"no EGL context on this machine: {out.stdout.strip()}")
    differ, again = (float(v) for v in out.stdout.split("DIFF")[1].split())
    assert differ > 1.0 and again == 0.0, out.stdout
