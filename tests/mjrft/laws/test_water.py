"""Water layer, buoyancy and force continuity at the water surface, the sand surface and region boundaries.

Bodies are moved kinematically (positions and velocities set by hand, then ``terrain.compute``), so each
force is exactly the coupler's for that state.
"""

import math

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.laws.wet import DRAG_COEFFICIENT, WATER_DENSITY, WATER_SKIN

SAND = "sea_sand_saturated"
DT = 1e-3

BODY = """<mujoco><compiler angle="radian"/><option timestep="{dt}" gravity="0 0 {g}"/><worldbody>
<body name="b" pos="0 0 0.5"><freejoint/>
  <geom name="g" type="{type}" size="{size}" pos="{gpos}" euler="{euler}" mass="0.05"/>
  <geom name="ballast" type="sphere" size="0.005" pos="0.03 0.01 0.02" mass="0.2" contype="0" conaffinity="0"/>
</body></worldbody></mujoco>"""


def body(type="box", size=(0.02, 0.01, 0.005), gpos=(0, 0, 0), euler=(0, 0, 0), g=-9.81):
    xml = BODY.format(dt=DT, g=g, type=type, size=" ".join(map(str, size)), gpos=" ".join(map(str, gpos)),
                      euler=" ".join(map(str, euler)))
    m = mujoco.MjModel.from_xml_string(xml)
    return m, mujoco.MjData(m)


def place(m, d, pos, vel=(0, 0, 0), quat=(1, 0, 0, 0)):
    d.qpos[:3], d.qpos[3:7] = pos, quat
    d.qvel[:3], d.qvel[3:] = vel, 0.0
    mujoco.mj_forward(m, d)


def force_at(t, m, d, pos, vel=(0, 0, 0), quat=(1, 0, 0, 0), dt=DT):
    place(m, d, pos, vel, quat)
    t.compute(d, dt)
    return t.wrench[1].copy()


# ---------------------------------------------------------------------------------------------- drag
def test_drag_on_submerged_box_is_c_rho_v2_on_leading_area():
    m, d = body()
    hx, hy, hz = 0.02, 0.01, 0.005
    t = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.004, water_depth=0.05)
    v = 0.3
    w = force_at(t, m, d, (0, 0, 0.025), (v, 0, 0))
    expected = -DRAG_COEFFICIENT * WATER_DENSITY * v * v * (2 * hy * 2 * hz)
    np.testing.assert_allclose(w[:3], [expected, 0, 0], rtol=1e-9, atol=1e-15)
    # per element: only the leading (+x) face feels it, each element C rho v^2 times its own area
    lead = t.normal[:, 0] > 0.5
    np.testing.assert_allclose(t.force[lead, 0], -DRAG_COEFFICIENT * WATER_DENSITY * v * v * t.area[lead],
                               rtol=1e-9)
    assert np.all(t.force[~lead] == 0)
    # oblique motion, down and forward at 45 deg: the +x and -z faces lead, each with n.v_hat = cos 45
    c = math.sqrt(0.5)
    w = force_at(t, m, d, (0, 0, 0.025), (v * c, 0, -v * c))
    s = (2 * hy * 2 * hz + 2 * hx * 2 * hy) * c
    np.testing.assert_allclose(w[:3], -DRAG_COEFFICIENT * WATER_DENSITY * v * v * s * np.array([c, 0, -c]),
                               rtol=1e-9, atol=1e-15)
    # quadratic in speed; the drag coefficient and water density are parameters
    t2 = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.004, water_depth=0.05,
                               drag_coefficient=1.0, water_density=1025.0)
    w2 = force_at(t2, m, d, (0, 0, 0.025), (2 * v, 0, 0))
    np.testing.assert_allclose(w2[0], -1.0 * 1025.0 * 4 * v * v * (2 * hy * 2 * hz), rtol=1e-9)
    # the water drag is viscous: its linearised damping 2 |F| / v is reported, no granular stiffness
    assert t2.terrain_state.damp[1] == pytest.approx(2 * abs(w2[0]) / (2 * v), rel=1e-9)
    assert t2.terrain_state.stiff[1, 0] == 0


def test_nothing_above_the_water_and_the_waterline_is_resolved():
    m, d = body()
    hw = 0.03
    t = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.0025, water_depth=hw)
    assert t.water_depth == hw and t.terrain_model.surface.top == pytest.approx(hw)
    # entirely above the water: culled, nothing
    w = force_at(t, m, d, (0, 0, hw + 0.0051), (0.2, 0, -0.1))
    assert np.all(w == 0) and not t.terrain_state.group_active.any()
    # straddling the water surface: elements above it feel nothing, elements a skin below it the full drag
    v = 0.2
    force_at(t, m, d, (0, 0, hw), (v, 0, 0))
    z = t.pos[:, 2]
    lead = t.normal[:, 0] > 0.5
    full = -DRAG_COEFFICIENT * WATER_DENSITY * v * v * t.area
    assert np.all(t.force[z >= hw] == 0)
    deep = lead & (z < hw - WATER_SKIN)
    assert deep.sum() >= 2
    np.testing.assert_allclose(t.force[deep, 0], full[deep], rtol=1e-9)
    skin = lead & (z < hw) & (z > hw - WATER_SKIN)
    np.testing.assert_allclose(t.force[skin, 0], full[skin] * (hw - z[skin]) / WATER_SKIN, rtol=1e-9)
    # a dry terrain (no water anywhere) gives nothing above the sand
    dry = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.0025)
    assert np.all(force_at(dry, m, d, (0, 0, 0.01), (v, 0, -v)) == 0)


def test_open_water_region_has_no_granular_bottom():
    m, d = body()
    t = mjrft.GranularTerrain(m, SAND, "water", geoms=["g"], resolution=0.004, water_depth=0.05)
    # below the sand surface (deeper than the skin) the law 'water' gives nothing at all
    assert np.all(force_at(t, m, d, (0, 0, -0.02), (0.1, 0, -0.1)) == 0)
    w = force_at(t, m, d, (0, 0, 0.02), (0.1, 0, 0))
    assert w[0] == pytest.approx(-DRAG_COEFFICIENT * WATER_DENSITY * 0.01 * (0.02 * 0.01), rel=1e-9)


# ---------------------------------------------------------------------------------------------- buoyancy
def _geom_centre(m, d):
    return d.geom_xpos[0].copy()


@pytest.mark.parametrize("euler", [(0, 0, 0), (0.3, -0.5, 1.1)])
def test_buoyancy_of_a_submerged_box_is_rho_g_v_at_its_centroid(euler):
    size = (0.02, 0.01, 0.005)
    m, d = body(size=size, gpos=(0.01, -0.02, 0.0), euler=euler)
    t = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.004, water_depth=0.2, buoyancy=True)
    w = force_at(t, m, d, (0.1, 0.2, 0.1))  # at rest, deep in the water: no drag
    V = 8 * np.prod(size)
    F = np.array([0, 0, WATER_DENSITY * 9.81 * V])
    np.testing.assert_allclose(w[:3], F, rtol=1e-9, atol=1e-12)
    # torque about the body's CoM (the ballast moves it away from the geom): the force acts at the box centre
    r = _geom_centre(m, d) - d.xipos[1]
    assert np.linalg.norm(r) > 0.01
    np.testing.assert_allclose(w[3:], np.cross(r, F), rtol=1e-9, atol=1e-12)
    # gravity is read from the model at each step; no buoyancy unless asked for
    m.opt.gravity[2] = -3.0
    np.testing.assert_allclose(force_at(t, m, d, (0.1, 0.2, 0.1))[2], WATER_DENSITY * 3.0 * V, rtol=1e-9)
    off = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.004, water_depth=0.2)
    assert np.all(force_at(off, m, d, (0.1, 0.2, 0.1)) == 0)


def test_buoyancy_partly_submerged_and_in_saturated_sand():
    size = (0.02, 0.01, 0.008)
    m, d = body(size=size)
    hw = 0.05
    t = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.004, water_depth=hw, buoyancy=True)
    rho_g = WATER_DENSITY * 9.81
    # waterline through the box's middle (an element edge: the midpoint rule is then exact): half the volume,
    # acting at the centroid of the lower half
    w = force_at(t, m, d, (0, 0, hw))
    V = 8 * np.prod(size)
    np.testing.assert_allclose(w[:3], [0, 0, rho_g * V / 2], rtol=1e-9, atol=1e-12)
    centroid = d.geom_xpos[0] - [0, 0, size[2] / 2]
    np.testing.assert_allclose(w[3:], np.cross(centroid - d.xipos[1], w[:3]), rtol=1e-9, atol=1e-12)
    # a waterline between element edges: the lift is still exact (only the flat bottom carries vertical
    # pressure); the side elements cut by the waterline move the point of action by less than their size
    w = force_at(t, m, d, (0.0, 0, hw + 0.003), quat=(math.cos(0.1), 0, math.sin(0.1), 0))
    assert w[2] > 0 and np.isfinite(w).all()
    w = force_at(t, m, d, (0, 0, hw + 0.003))
    np.testing.assert_allclose(w[:3], [0, 0, rho_g * 4 * size[0] * size[1] * (size[2] - 0.003)], rtol=1e-9,
                               atol=1e-12)
    # the force grows continuously as the box sinks through the water surface (pressure is 0 there)
    zs = np.arange(hw + 0.012, hw - 0.012, -1e-4)
    fz = np.array([force_at(t, m, d, (0, 0, zz))[2] for zz in zs])
    assert fz[0] == 0 and fz[-1] == pytest.approx(rho_g * V, rel=1e-9)
    assert np.max(np.abs(np.diff(fz))) < rho_g * V * 1e-4 / (2 * size[2]) * 1.5
    # buried in saturated sand at rest (no granular force without motion): the pore water still lifts it,
    # from the water surface hw above the sand
    w = force_at(t, m, d, (0, 0, -0.03))
    np.testing.assert_allclose(w[:3], [0, 0, rho_g * V], rtol=1e-9, atol=1e-12)
    sat = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.004, buoyancy=True)  # no free water
    np.testing.assert_allclose(force_at(sat, m, d, (0, 0, -0.03))[:3], [0, 0, rho_g * V], rtol=1e-9, atol=1e-12)
    dry = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.004, buoyancy=True)
    assert np.all(force_at(dry, m, d, (0, 0, -0.03)) == 0)


def test_buoyancy_of_a_sphere_and_a_floating_box():
    m, d = body(type="sphere", size=(0.01,))
    t = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.002, water_depth=0.1, buoyancy=True)
    w = force_at(t, m, d, (0, 0, 0.05))
    V = 4 / 3 * math.pi * 0.01 ** 3
    assert w[2] == pytest.approx(WATER_DENSITY * 9.81 * V, rel=0.01)
    np.testing.assert_allclose(w[:2], 0, atol=1e-12)
    np.testing.assert_allclose(w[3:], np.cross(_geom_centre(m, d) - d.xipos[1], w[:3]), rtol=1e-6, atol=1e-12)
    # a light box dropped on deep water floats at the draft where buoyancy carries its weight
    xml = """<mujoco><option timestep="0.001"/><worldbody><body name="b" pos="0 0 0.06"><freejoint/>
      <geom name="g" type="box" size="0.03 0.03 0.01" mass="0.0144"/></body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    t = mjrft.GranularTerrain(m, SAND, "water", resolution=0.005, water_depth=0.05, buoyancy=True)
    z = []
    for _ in range(1000):  # it bobs about the equilibrium; the v^2 drag damps small oscillations slowly
        t.step(d, 2)
        z.append(d.qpos[2])
    z = np.array(z)
    draft = 0.05 - (np.mean(z[500:]) - 0.01)
    print(f"floating box: draft {draft * 1e3:.3f} mm (Archimedes 4 mm), bobbing {np.ptp(z[:250]) * 1e3:.2f} -> "
          f"{np.ptp(z[-250:]) * 1e3:.2f} mm peak to peak")
    assert draft == pytest.approx(0.0144 / (WATER_DENSITY * 0.06 * 0.06), rel=0.02)  # 4 mm
    assert np.ptp(z[-250:]) < 0.5 * np.ptp(z[:250])  # the drag takes energy out, nothing puts it in


# ---------------------------------------------------------------------------------------------- continuity
def _path(t, m, d, start, vel, n, elements=None):
    """Body force at each step of a straight kinematic path (memory advanced by dt each step); the element
    forces of every step are appended to ``elements`` if given."""
    t.reset()
    start, vel = np.asarray(start, float), np.asarray(vel, float)
    out = []
    for k in range(n):
        out.append(force_at(t, m, d, start + k * DT * vel, vel)[:3])
        if elements is not None:
            elements.append(t.force.copy())
    return np.array(out)


def _steps_near(f, xs, x0, window):
    """(largest force change on the step straddling x0, largest change on the other steps within window)."""
    df = np.linalg.norm(np.diff(f, axis=0), axis=1)
    lo, hi = np.minimum(xs[:-1], xs[1:]), np.maximum(xs[:-1], xs[1:])
    straddle = (lo <= x0) & (x0 <= hi)
    near = (np.abs(0.5 * (lo + hi) - x0) < window) & ~straddle
    return df[straddle].max(), df[near].max()


def _assert_no_jump(f, xs, x0, label, window=3e-3):
    jump, own = _steps_near(f, xs, x0, window)
    print(f"{label}: change on the crossing step {jump:.4g} N, element's own change per step nearby {own:.4g} N")
    assert np.isfinite(f).all()
    assert jump <= own * (1 + 1e-6) + 1e-12


@pytest.mark.parametrize("tilt", [0.0, 0.4])
def test_force_continuous_through_water_surface_and_sand_surface(tilt):
    """A plate driven down at 0.1 m/s through 2 cm of water into saturated sand, with buoyancy."""
    m, d = body(size=(0.01, 0.01, 0.001), euler=(0, tilt, 0))
    hw, v = 0.02, 0.1
    t = mjrft.GranularTerrain(m, SAND, "wet", geoms=["g"], resolution=0.01, water_depth=hw, buoyancy=True)
    vel = np.array([0.3 * v, 0.0, -v])
    z0 = hw + 0.015
    n = int((z0 + 0.01) / (v * DT))
    f = _path(t, m, d, (0, 0, z0), vel, n)
    zc = z0 - np.arange(n) * DT * v  # centre height
    assert f[0].tolist() == [0, 0, 0] and np.linalg.norm(f[-1]) > 0.05  # dry above the water, deep in sand
    offsets = np.unique(np.round(t.pos[:, 2] - zc[-1], 9))  # element heights relative to the plate's centre
    assert len(offsets) >= (2 if tilt == 0 else 5)
    crossings = [(surf - o, f"{label} tilt {tilt}, element at {o * 1e3:+.2f} mm")
                 for surf, label in ((hw, "water surface"), (0.0, "sand surface")) for o in offsets]
    for x0, label in crossings:  # every element's crossing of each surface
        _assert_no_jump(f, zc, x0, label)
    if tilt:
        return
    # the criterion has teeth: without the 1 mm water skin (a hard switch at the water surface) it fails
    hard = mjrft.GranularTerrain(m, mjrft.get_medium(SAND).with_extra(water_skin=1e-9), "wet", geoms=["g"],
                                 resolution=0.01, water_depth=hw)
    fh = _path(hard, m, d, (0, 0, z0), vel, n)
    jumps = [_steps_near(fh, zc, hw - o, 3e-3) for o in offsets]
    assert any(j > 2 * o for j, o in jumps)


def test_force_continuous_across_a_region_boundary():
    """A vertical plate dragged along x at 2 cm depth from dry poppy seeds into saturated sand under water."""
    m, d = body(size=(0.001, 0.01, 0.01))
    b, v, depth = 0.0, 0.05, 0.02
    regions = [(b, SAND, "wet", 0.02)]
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01, regions=regions, buoyancy=True)
    assert t.transition == 0.01
    x0 = b - 0.015
    n = int(0.03 / (v * DT))
    el = []
    f = _path(t, m, d, (x0, 0, -depth), (v, 0, 0), n, el)
    xs = x0 + np.arange(n) * DT * v
    # both sides are steady (memory settled): the force there is each region's own
    fa, fb = f[100], f[-1]
    assert np.linalg.norm(fb - fa) > 0.1 * np.linalg.norm(fa)
    assert np.allclose(f[100:150], fa, rtol=1e-9) and np.allclose(f[-50:], fb, rtol=1e-9)
    # across the boundary each element's force moves from its value on one side to the other's in equal
    # steps of |fb_e - fa_e| v dt / transition; the body's step is at most their sum
    df = np.linalg.norm(np.diff(f[100:], axis=0), axis=1)
    blend_step = np.linalg.norm(el[-1] - el[100], axis=1).sum() * v * DT / t.transition
    print(f"region boundary: largest step {df.max():.4g} N, blend step {blend_step:.4g} N, "
          f"forces {np.linalg.norm(fa):.4g} -> {np.linalg.norm(fb):.4g} N")
    assert df.max() <= blend_step * (1 + 1e-6)
    _assert_no_jump(f[100:], xs[100:], b, "region boundary", window=t.transition)
    # weights: half and half on the boundary, pure at +-transition/2
    np.testing.assert_allclose(t.region_weights([b - 0.005, b, b + 0.0025, b + 0.005], 0),
                               [[1, 0], [0.5, 0.5], [0.25, 0.75], [0, 1]], atol=1e-12)
    # a hard switch (transition 0) jumps by the whole difference in one step
    hard = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], resolution=0.01, regions=regions,
                                 buoyancy=True, transition=0.0)
    fh = _path(hard, m, d, (x0, 0, -depth), (v, 0, 0), n)
    assert np.linalg.norm(np.diff(fh[100:], axis=0), axis=1).max() > 0.5 * np.linalg.norm(fb - fa)


def test_dry_scene_cost_structure_unchanged():
    """A dry scene culls at the sand surface (water raises the cull height only where there is water)."""
    m, d = body()
    dry = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], regions=[(0.5, "glass3_cp", "rft")])
    assert dry.terrain_model.surface.top == dry.surface == 0.0 and dry.water_depth == 0.0
    wet = mjrft.GranularTerrain(m, "poppy_cp", "rft", geoms=["g"], regions=[(0.5, SAND, "wet", 0.03)])
    assert wet.terrain_model.surface.top == pytest.approx(0.03)
    # an element above the dry strip's sand, under the water height of the other strip, feels nothing
    assert np.all(force_at(wet, m, d, (0, 0, 0.015), (0.1, 0, -0.1)) == 0)
    assert np.all(wet.force == 0)
