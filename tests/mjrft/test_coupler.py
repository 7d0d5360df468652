"""The MuJoCo coupler: current kinematics, wrench bookkeeping, settling, rest, callbacks and errors."""

import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft import laws
from mjrft.laws.common import LEAD_EPS

BOX = """<mujoco><option timestep="{dt}"/><worldbody>
<body name="foot" pos="0 0 {z}"><freejoint/><geom name="plate" type="box" size="{hx} {hy} {hz}" mass="{mass}"/></body>
</worldbody></mujoco>"""

LEGGED = """<mujoco><option timestep="0.001"/><worldbody>
<body name="torso" pos="0 0 0.05"><freejoint/><geom type="box" size=".06 .03 .01" mass="0.1"/>
  <body name="leg1" pos=".05 0 -.01"><joint name="h1" type="hinge" axis="0 1 0" damping="0.01"/>
    <geom name="shin1" type="capsule" fromto="0 0 0 0.01 0 -.03" size=".004" mass="0.01"/></body>
  <body name="leg2" pos="-.05 0 -.01"><joint name="h2" type="hinge" axis="0 1 0" damping="0.01"/>
    <geom name="shin2" type="capsule" fromto="0 0 0 -0.01 0 -.03" size=".004" mass="0.01"/></body>
</body></worldbody>
<actuator><position joint="h1" kp="2"/><position joint="h2" kp="2"/></actuator></mujoco>"""


def box(mass=2.0, z=0.005, dt=0.002, hx=0.05, hy=0.05, hz=0.005):
    m = mujoco.MjModel.from_xml_string(BOX.format(mass=mass, z=z, dt=dt, hx=hx, hy=hy, hz=hz))
    return m, mujoco.MjData(m)


def element_kinematics(m, d, terrain):
    """Independent world positions, normals and velocities of the terrain's elements (jacobians)."""
    pos, nrm, vel = [], [], []
    for i in range(terrain.n_elements):
        b = terrain.elem_body[i]
        R = d.xmat[b].reshape(3, 3)
        p = d.xpos[b] + R @ terrain.elements.pos[i]
        jacp = np.zeros((3, m.nv))
        mujoco.mj_jac(m, d, jacp, None, p, b)
        pos.append(p)
        nrm.append(R @ terrain.elements.normal[i])
        vel.append(jacp @ d.qvel)
    return np.array(pos), np.array(nrm), np.array(vel)


@pytest.mark.filterwarnings("ignore::mjrft.TerrainStabilityWarning")  # v_eps = 1e-9 is deliberately stiff
@pytest.mark.slow
def test_uses_current_kinematics_and_wrench_is_brute_force_sum():
    m = mujoco.MjModel.from_xml_string(LEGGED)
    d = mujoco.MjData(m)
    # pure law (no memory): forces must equal the law evaluated on this step's kinematics
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", bodies=["torso", "leg1", "leg2"], resolution=0.004,
                              yield_displacement=0.0, v_eps=1e-9)
    rng = np.random.default_rng(0)
    d.qpos[2] = 0.035
    d.qpos[7:] = [0.4, -0.3]
    d.qvel[:] = rng.normal(scale=0.2, size=m.nv)
    d.qvel[2] = -0.1
    # reference kinematics from the state the step starts from (mj_step1 does not move qpos)
    ref = mujoco.MjData(m)
    ref.qpos[:], ref.qvel[:] = d.qpos, d.qvel
    mujoco.mj_forward(m, ref)
    pos, nrm, vel = element_kinematics(m, ref, t)
    t.step(d)
    # positions are kept for every element of a geom whose bounding box reaches the surface; the others
    # (culled: no element work at all) are exactly the geoms whose lowest element is above it
    near = np.repeat(t.terrain_state.group_active, np.diff(t.terrain_model.elements.group_start))
    assert near.any() and not near.all()
    np.testing.assert_allclose(t.pos[near], pos[near], atol=1e-12)
    assert np.all(pos[~near, 2] > t.surface)
    below = pos[:, 2] < t.surface  # velocities and normals are only evaluated below the surface
    assert below.sum() > 20
    np.testing.assert_allclose(t.vel[below], vel[below], atol=1e-10)
    np.testing.assert_allclose(t.normal[below], nrm[below], atol=1e-12)
    depth = t.surface - pos[:, 2]
    f = laws.rft(depth, nrm, vel, t.area, "poppy_cp")
    assert np.count_nonzero(np.linalg.norm(f, axis=1)) > 20
    # buried faces turned away from their motion, which the kernel leaves out of the batched law, are among them
    trailing = below & (np.einsum("ij,ij->i", nrm, vel) < -LEAD_EPS * np.linalg.norm(vel, axis=1))
    assert trailing.sum() > 5 and np.all(t.force[trailing] == 0.0)
    np.testing.assert_allclose(t.force, f, rtol=1e-9, atol=1e-12)
    for b in (1, 2, 3):
        sel = t.elem_body == b
        F = f[sel].sum(axis=0)
        tau = np.cross(pos[sel] - ref.xipos[b], f[sel]).sum(axis=0)
        np.testing.assert_allclose(t.wrench[b], np.concatenate([F, tau]), rtol=1e-9, atol=1e-12)
    # and MuJoCo integrated exactly that wrench: same next state as applying it by hand
    by_hand = mujoco.MjData(m)
    by_hand.qpos[:], by_hand.qvel[:] = ref.qpos, ref.qvel
    by_hand.xfrc_applied[:] = t.wrench
    mujoco.mj_step(m, by_hand)
    np.testing.assert_allclose(d.qvel, by_hand.qvel, atol=1e-10)
    # the terrain's contribution was taken out of xfrc_applied again
    assert np.all(d.xfrc_applied == 0)


def test_user_xfrc_applied_is_kept():
    m, d = box()
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft")
    d.xfrc_applied[1] = [1.0, 2.0, 3.0, 0.1, 0.2, 0.3]
    t.step(d, 20)
    np.testing.assert_array_equal(d.xfrc_applied[1], [1.0, 2.0, 3.0, 0.1, 0.2, 0.3])


def ramp_gravity_and_settle(m, d, t, ramp=1.0, hold=1.0):
    """Load the foot quasi-statically: gravity ramps from 0 to g, then holds."""
    dt = m.opt.timestep
    z, energy = [], []
    for k in range(int((ramp + hold) / dt)):
        m.opt.gravity[2] = -9.81 * min(1.0, k * dt / ramp)
        t.step(d)
        z.append(d.qpos[2])
    return np.array(z)


@pytest.mark.parametrize("law", ["rft", "rft3d"])
def test_flat_box_settles_at_analytic_depth(law):
    mass, area = 2.0, 0.1 * 0.1
    m, d = box(mass=mass)
    t = mjrft.GranularTerrain(m, "poppy_cp", law, resolution=0.01)
    z = ramp_gravity_and_settle(m, d, t)
    sink = -(z[-1] - 0.005)
    per_depth = t.medium.alpha_z_down if law == "rft" else mjrft.media.RFT3D_DOWN * t.medium.xi_n
    expected = mass * 9.81 / (per_depth * area)
    assert sink == pytest.approx(expected, rel=0.10)
    # no creep after settling: last 0.5 s moves < 1 mm/s (in fact not at all)
    k = int(0.5 / m.opt.timestep)
    assert abs(z[-1] - z[-k]) / 0.5 < 1e-3
    assert np.max(np.abs(np.diff(z[-k:]))) / m.opt.timestep < 1e-3


def test_dropped_box_holds_still_without_energy_gain():
    mass = 2.0
    m, d = box(mass=mass, z=0.02)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01)
    dt = m.opt.timestep
    energy, z = [], []
    for _ in range(int(2.0 / dt)):
        t.step(d)
        energy.append(0.5 * mass * d.qvel[:3] @ d.qvel[:3] + mass * 9.81 * d.qpos[2])
        z.append(d.qpos[2])
    energy = np.array(energy)
    z = np.array(z)
    assert np.all(energy <= energy[0] + 1e-9)  # never above the initial energy
    # after the deepest point only the grains' elastic store comes back: a rebound below delta
    assert np.max(z[np.argmin(z):]) - np.min(z) <= t.yield_displacement
    # penetration of a dropped plate follows the energy balance of a linear-in-depth yield:
    # d = d0 + sqrt(d0^2 + 2 d0 h) with h the fall height; grains do not spring back
    d0 = mass * 9.81 / (t.medium.alpha_z_down * 0.01)
    h = 0.015
    assert -(z[-1] - 0.005) == pytest.approx(d0 + np.sqrt(d0 ** 2 + 2 * d0 * h), rel=0.1)
    assert abs(z[-1] - z[-250]) < 1e-6  # at rest
    assert np.all(np.abs(d.qvel) < 1e-4)


def test_resting_body_on_a_slope_load_does_not_creep():
    """A sideways push below yield is held like a solid: no drift after the load is applied."""
    m, d = box(mass=1.0)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01)
    ramp_gravity_and_settle(m, d, t, ramp=0.5, hold=0.5)
    d.xfrc_applied[1, 0] = 0.5  # well below the horizontal yield force at this depth
    t.step(d, 500)
    x0 = d.qpos[0]
    t.step(d, 500)
    assert abs(d.qpos[0] - x0) / 0.5 < 2e-5  # < 0.02 mm/s, against the 1 mm/s requirement


def test_callback_mode_matches_step_mode():
    m1, d1 = box(z=0.01)
    m2, d2 = box(z=0.01)
    t1 = mjrft.GranularTerrain(m1, "poppy_cp", "rft", resolution=0.01)
    t2 = mjrft.GranularTerrain(m2, "poppy_cp", "rft", resolution=0.01)
    t1.step(d1, 300)
    with t2:
        for _ in range(300):
            mujoco.mj_step(m2, d2)
    assert mujoco.get_mjcb_passive() is None
    np.testing.assert_allclose(d2.qpos, d1.qpos, atol=1e-9)
    assert np.all(d2.xfrc_applied == 0)


def test_mjcf_custom_configuration():
    xml = BOX.format(mass=1, z=0.1, dt=0.002, hx=.02, hy=.02, hz=.02).replace(
        "<worldbody>", """<custom><text name="mjrft:medium" data="glass3_cp"/><text name="mjrft:law" data="rft3d"/>
        <text name="mjrft:bodies" data="foot"/><numeric name="mjrft:surface" data="0.05"/>
        <numeric name="mjrft:resolution" data="0.02"/></custom><worldbody>""")
    m = mujoco.MjModel.from_xml_string(xml)
    t = mjrft.GranularTerrain(m)
    assert (t.medium.name, t.law, t.surface, t.resolution) == ("glass3_cp", "rft3d", 0.05, 0.02)
    assert t.n_elements == 24  # 2 x 2 elements per 4 cm face at 2 cm
    t2 = mjrft.GranularTerrain(m, medium="poppy_lp")  # arguments override the file
    assert t2.medium.name == "poppy_lp" and t2.law == "rft3d"


def test_geoms_far_above_are_culled():
    m, d = box(z=1.0)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft")
    t.step(d, 3)
    assert not t.terrain_state.group_active.any()
    assert np.all(t.force == 0) and np.all(t.wrench == 0)


def test_reset_on_time_going_backwards():
    m, d = box(z=0.0)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01)
    t.step(d, 200)
    assert np.any(t.terrain_state.u != 0)
    mujoco.mj_resetData(m, d)
    t.step(d, 1)
    assert np.all(np.abs(t.terrain_state.u) <= 1e-3)


def test_sinkage_and_contact_outputs():
    m, d = box(z=0.0)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01)
    t.step(d, 200)
    sink = t.sinkage()
    assert sink[1] == pytest.approx(t.depth.max()) and sink[0] == 0
    assert t.contact_mask().sum() > 0


def test_stability_warning_for_too_large_timestep():
    m, d = box(mass=0.001, z=0.0, dt=0.01)  # 1 g plate, 10 ms step: beyond the limit
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01, yield_displacement=1e-4)
    with pytest.warns(mjrft.TerrainStabilityWarning, match="exceeds the stability limit.*body 'foot'"):
        t.step(d, 100)


def test_default_settings_are_inside_the_stability_limit():
    m, d = box(mass=2.0, z=0.0, dt=0.002)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("error", mjrft.TerrainStabilityWarning)
        ramp_gravity_and_settle(m, d, t, ramp=0.3, hold=0.3)


def test_nonfinite_force_raises_naming_body_and_time():
    m, d = box(z=0.0)
    huge = mjrft.Medium("huge", tuple(c * 5e302 for c in mjrft.generic.coeffs), 1e308)  # finite, sums overflow
    t = mjrft.GranularTerrain(m, huge, "rft")
    d.qvel[2] = -0.1
    with pytest.raises(mjrft.NonFiniteError, match=r"non-finite granular force on body 'foot' at t = 0 s"):
        t.step(d)
    assert np.all(np.isfinite(d.xfrc_applied)) and np.all(d.xfrc_applied == 0)


def test_nonfinite_state_raises_naming_body_and_time():
    m, d = box(z=0.0)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft")
    t.step(d, 5)
    d.cvel[1, 5] = np.nan  # e.g. corrupted by other code between mj_step1 and the terrain
    with pytest.raises(mjrft.NonFiniteError, match=r"non-finite state .* on body 'foot' at t = 0\.01"):
        t.compute(d)


def test_construction_errors():
    m, _ = box()
    with pytest.raises(ValueError, match="unknown medium 'mud'.*glass03_cp.*poppy_cp"):
        mjrft.GranularTerrain(m, "mud")
    with pytest.raises(ValueError, match="unknown law .fancy.; valid choices: depth_only, .*rft, rft3d"):
        mjrft.GranularTerrain(m, "poppy_cp", "fancy")
    with pytest.raises(ValueError, match="unknown geom 'sole'.*plate"):
        mjrft.GranularTerrain(m, geoms=["sole"])
    with pytest.raises(ValueError, match="unknown body 'shin'.*foot"):
        mjrft.GranularTerrain(m, bodies=["shin"])
    for kw, msg in [({"resolution": -0.01}, "resolution must be finite and > 0"),
                    ({"resolution": float("nan")}, "resolution must be finite"),
                    ({"surface": float("inf")}, "surface must be finite"),
                    ({"yield_displacement": -1e-3}, "yield_displacement must be finite and >= 0"),
                    ({"damping_time": float("nan")}, "damping_time must be finite")]:
        with pytest.raises(ValueError, match=msg):
            mjrft.GranularTerrain(m, **kw)
    plane = mujoco.MjModel.from_xml_string('<mujoco><worldbody><geom name="floor" type="plane" size="1 1 1"/>'
                                           '</worldbody></mujoco>')
    with pytest.raises(ValueError, match="geom 'floor' has type mjGEOM_PLANE; supported"):
        mjrft.GranularTerrain(plane, geoms=["floor"])


def test_regions_pick_the_law_by_position():
    m, d = box(z=0.0, hx=0.1)
    t = mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.01, regions=[(0.0, "glass3_cp", "depth_only")])
    t.step(d, 50)
    assert set(np.unique(t.region[t.depth > 0])) == {0, 1}
    below = t.depth > 0
    assert np.all((t.region[below] == 1) == (t.pos[below, 0] >= 0))
    with pytest.raises(ValueError, match="sorted by increasing x_min"):
        mjrft.GranularTerrain(m, regions=[(0.1, "poppy_cp", "rft"), (0.0, "poppy_cp", "rft")])


def test_min_stable_timesteps_equals_both_parts():
    """min_stable_timesteps (one set of jacobians for both parts) returns exactly min_stable_timestep's springs and
    depth limits, on every step of a walking hexapod (finite ones included), and only for the data last stepped."""
    from mjrft.models import hexapod_model
    m = hexapod_model()
    d = mujoco.MjData(m)
    t = mjrft.GranularTerrain(m, resolution=0.01)
    finite = 0
    for _ in range(60):
        d.ctrl[:] = 2 * np.pi * 2.0 * d.time + np.array([0.0, np.pi, 0.0, np.pi, 0.0, np.pi])
        t.step(d, 5)
        pair = t.min_stable_timesteps(d)
        assert pair == (t.min_stable_timestep(d, "springs"), t.min_stable_timestep(d, "depth"))
        finite += np.isfinite(pair[0]) and np.isfinite(pair[1]) and pair[0] != pair[1]
    assert finite > 30
    with pytest.raises(ValueError, match="needs the MjData this terrain last stepped"):
        t.min_stable_timesteps(mujoco.MjData(m))


@pytest.mark.filterwarnings("ignore::mjrft.ValidityRangeWarning")  # the legs hit the sand at 1.2 m/s
def test_actuator_power_is_the_mean_over_every_physics_step_of_a_step_call():
    m = mujoco.MjModel.from_xml_string(LEGGED)
    d, d1 = mujoco.MjData(m), mujoco.MjData(m)
    t, t1 = (mjrft.GranularTerrain(m, "poppy_cp", "rft", resolution=0.004) for _ in range(2))
    assert t.actuator_power == 0.0
    for k in range(6):
        d.ctrl[:] = d1.ctrl[:] = [np.sin(3.0 * k), np.cos(2.0 * k)]
        t.step(d, 10)
        per_step = []
        for _ in range(10):  # the same ten physics steps, the power read off MjData after each
            t1.step(d1, 1)
            per_step.append(np.sum(np.abs(d1.actuator_force * d1.actuator_velocity)))
        assert np.array_equal(d.qpos, d1.qpos)
        assert t.actuator_power == pytest.approx(np.mean(per_step), rel=1e-12, abs=1e-15)
        # control: the power at the call's last physics step alone (a sample) is not the mean
        if k > 0:
            assert abs(per_step[-1] - np.mean(per_step)) > 1e-3 * np.mean(per_step)


def test_step_counts_are_whole_and_a_non_finite_model_is_refused_before_it_steps():
    m, d = box()
    t = mjrft.GranularTerrain(m, "poppy_cp", resolution=0.01)
    for bad in (1.5, -1, float("nan"), "2", None, True):
        with pytest.raises(ValueError, match="nstep must be a whole number of steps >= 0"):
            t.step(d, bad)
    t.step(d, 2.0)  # a float equal to a whole number is a count
    t.step(d, np.int32(1))
    assert d.time == pytest.approx(3 * m.opt.timestep)
    m.body_mass[1] = np.nan  # edited after construction: refused at the next reset
    d.time = 0.0
    with pytest.raises(ValueError, match="body 'foot' has a non-finite mass"):
        t.step(d, 1)
    with pytest.raises(ValueError, match="body 'foot' has a non-finite mass"):
        mjrft.GranularTerrain(m, "poppy_cp", resolution=0.01)
