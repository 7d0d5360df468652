"""The dry inertial regime (mjrft.laws.inertial): law, kernel, options, stability limit and validity range."""

from __future__ import annotations

import math
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft import laws
from mjrft.errors import TerrainStabilityWarning, ValidityRangeWarning
from mjrft.laws import inertial as inl
from mjrft.media import MEDIA
from mjrft.params import P_INERTIA
from mjrft.laws.registry import parameter_vector

GLASS = MEDIA["glass3_cp"]
DOWN = np.array([[0.0, 0.0, -1.0]])  # a horizontal face pushed down (outward normal down)
AREA = 4.2e-4


def _fz(v, depth=0.003, inertial=True, law="rft", medium="glass3_cp"):
    return laws.apply_law(law, depth, DOWN, [[0.0, 0.0, -v]], AREA, medium, inertial=inertial)[0]


def test_coefficient_from_the_papers_numbers():
    # C = m g (6.5 - 1) / (rho_bulk 3 A_leg (1 - 0.25^2)), DynaRoACH paper sec. 3.2 (module docstring)
    c = 0.025 * 9.81 * 5.5 / (2470 * 0.63 * 3 * 1.4e-4 * (1.0 - 0.0625))
    assert inl.INERTIAL_DRAG == pytest.approx(c, rel=1e-12)
    assert inl.INERTIAL_DRAG == pytest.approx(2.20, abs=0.005)
    assert GLASS.critical_speed == pytest.approx(math.sqrt(2 * 9.81 * 3.2e-3))
    assert GLASS.critical_speed == pytest.approx(0.25, abs=0.002)  # the paper's v_c = 25 cm/s


@pytest.mark.parametrize("law", ["rft", "rft3d", "depth_only"])
def test_zero_speed_and_below_vc_equal_the_quasi_static_law(law):
    assert np.all(_fz(0.0, law=law) == 0.0)
    vc = GLASS.critical_speed
    for v in (1e-6, 0.1, 0.999 * vc, vc):
        assert np.array_equal(_fz(v, law=law), _fz(v, law=law, inertial=False))


@pytest.mark.parametrize("law", ["rft", "rft3d", "depth_only"])
def test_across_vc_continuous_then_quadratic(law):
    vc = GLASS.critical_speed
    off = _fz(0.5, law=law, inertial=False)  # rate-independent: the same at every speed
    just = _fz(vc * (1 + 1e-9), law=law) - off
    assert abs(just[2]) < 1e-9
    cr = inl.INERTIAL_DRAG * GLASS.rho_bulk
    for v in (0.3, 0.6, 1.0, 2.0):
        extra = _fz(v, law=law) - off
        assert extra[2] == pytest.approx(cr * AREA * (v * v - vc * vc), rel=1e-12)
        assert extra[0] == 0.0 and extra[1] == 0.0


def test_direction_skin_and_trailing_faces():
    vc2 = GLASS.critical_speed ** 2
    cr = inl.INERTIAL_DRAG * GLASS.rho_bulk
    # a face at 60 degrees to the motion: its normal speed squared, along its normal
    n = np.array([[math.sin(math.radians(60)), 0.0, -math.cos(math.radians(60))]])
    v = np.array([[0.0, 0.0, -1.0]])
    f = laws.rft(0.01, n, v, AREA, "glass3_cp", inertial=True) - laws.rft(0.01, n, v, AREA, "glass3_cp")
    u = 0.5
    assert np.allclose(f[0], -cr * AREA * (u * u - vc2) * n[0], rtol=1e-12)
    # trailing face (moving away from its normal): nothing
    g = laws.rft(0.01, -n, v, AREA, "glass3_cp", inertial=True) - laws.rft(0.01, -n, v, AREA, "glass3_cp")
    assert np.all(g == 0.0)
    # the 1 mm skin: half the pressure at 0.5 mm, none at or above the surface
    half = _fz(1.0, depth=0.0005) - _fz(1.0, depth=0.0005, inertial=False)
    full = _fz(1.0, depth=0.002) - _fz(1.0, depth=0.002, inertial=False)
    assert half[2] == pytest.approx(0.5 * full[2], rel=1e-12)
    assert np.all(_fz(1.0, depth=0.0) == 0.0) and np.all(_fz(1.0, depth=-0.01) == 0.0)


def test_huge_speed_is_finite_and_bad_input_is_rejected():
    f = _fz(1e6)
    assert np.all(np.isfinite(f)) and f[2] > 1e11
    with pytest.raises(ValueError, match="dry laws"):
        laws.apply_law("wet", 0.01, DOWN, [[0, 0, -1.0]], AREA, "sea_sand_saturated", inertial=True)
    with pytest.raises(ValueError, match="grain"):  # the generic profile has no grains, so no v_c / rho
        laws.rft(0.01, DOWN, [[0, 0, -1.0]], AREA, "generic", inertial=True)
    with pytest.raises(ValueError, match="inertial_drag"):
        laws.apply_law("rft", 0.01, DOWN, [[0, 0, -1.0]], AREA, "glass3_cp", inertial=True, inertial_drag=-1.0)


def test_off_by_default_costs_nothing_in_the_parameters():
    assert all(np.all(parameter_vector(m)[P_INERTIA:P_INERTIA + 3] == 0.0) for m in MEDIA.values())


PLATE = """<mujoco><option gravity="0 0 0" timestep="{dt}"/>
<worldbody><body name="plate" pos="0 0 -0.003"><freejoint/>
<geom type="box" size="0.0102 0.0102 0.001" mass="{mass}"/></body></worldbody>
{custom}</mujoco>"""


def _plate(v, dt=1e-3, mass=0.02, custom=""):
    model = mujoco.MjModel.from_xml_string(PLATE.format(dt=dt, mass=mass, custom=custom))
    data = mujoco.MjData(model)
    data.qvel[2] = -v
    mujoco.mj_forward(model, data)
    return model, data


@pytest.mark.parametrize("law,regions", [("rft", None), ("rft3d", None), ("depth_only", None),
                                          ("rft", [(-0.001, "glass3_cp", "rft3d")])])
def test_kernel_adds_the_law_on_every_path(law, regions):
    """Batched Li-RFT pass, the single-region general path and a region blend: the terrain's force minus
    the quasi-static terrain's force is the pure law's inertial force on the buried elements."""
    model, data = _plate(0.8)
    kw = dict(medium="glass3_cp", law=law, resolution=0.004, yield_displacement=0.0, v_eps=1e-6,
              regions=regions, transition=0.004 if regions else None)
    off = mjrft.GranularTerrain(model, **kw)
    on = mjrft.GranularTerrain(model, inertial=True, **kw)
    off.compute(data)
    on.compute(data)
    buried = on.depth > 0
    assert buried.any()
    expect = np.zeros((on.n_elements, 3))
    p = np.zeros(mjrft.params.P_SIZE)
    inl.set_inertial(p, GLASS)
    inl.add_inertial(np.ascontiguousarray(on.depth), on.normal, on.vel, on.area, p, expect)
    assert np.abs(expect).sum() > 0
    assert np.allclose(on.force - off.force, expect, rtol=1e-9, atol=1e-12)
    assert on.wrench[1, 2] - off.wrench[1, 2] == pytest.approx(expect[:, 2].sum(), rel=1e-9)


def test_custom_keys_and_option_errors():
    model, data = _plate(0.8, custom='<custom><numeric name="mjrft:inertial" data="1"/>'
                                      '<numeric name="mjrft:inertial_drag" data="3"/>'
                                      '<text name="mjrft:medium" data="glass3_cp"/></custom>')
    t = mjrft.GranularTerrain(model)
    assert t.inertial and t.inertial_drag == 3.0
    assert t.terrain_model.regions.params[0, P_INERTIA] == pytest.approx(3.0 * GLASS.rho_bulk)
    assert mjrft.GranularTerrain(model, inertial=False).terrain_model.regions.params[0, P_INERTIA] == 0.0
    with pytest.raises(ValueError, match="grain"):
        mjrft.GranularTerrain(model, medium="generic", inertial=True)
    with pytest.raises(ValueError, match="dry law"):
        mjrft.GranularTerrain(model, medium="sea_sand_saturated", law="wet", inertial=True)
    with pytest.raises(ValueError, match="inertial must be"):
        mjrft.GranularTerrain(model, inertial=2)


def test_stability_limit_of_the_damper():
    """The regime's damper c = 2 C rho A u: stable iff dt < 2 m / c (no stiffness in the viscous mode's
    limit below v_c: only the damper). Zero speed adds nothing; above v_c the limit falls as 1/u."""
    kw = dict(medium="glass3_cp", resolution=0.004, yield_displacement=0.0, v_eps=1e3)  # tiny viscous damping
    limits = {}
    for v in (0.0, 0.2, 1.0, 10.0):
        model, data = _plate(v)
        t = mjrft.GranularTerrain(model, inertial=True, **kw)
        t.compute(data)
        limits[v] = t.stable_timestep(data, "springs")[1]
        if v < GLASS.critical_speed:  # at rest and below v_c: no damper, the quasi-static limit unchanged
            off = mjrft.GranularTerrain(model, **kw)
            off.compute(data)
            assert t.terrain_state.inert[1, 0] == 0.0
            assert limits[v] == off.stable_timestep(data, "springs")[1]
    # above v_c: the damper of the whole plate (every buried bottom element, skin weight 1: 3 mm deep)
    model, data = _plate(10.0)
    t = mjrft.GranularTerrain(model, inertial=True, **kw)
    t.compute(data)
    bottom = (t.depth > 0.001) & (t.normal[:, 2] < -0.99)
    c = 2 * inl.INERTIAL_DRAG * GLASS.rho_bulk * t.area[bottom].sum() * 10.0
    mass = model.body_mass[1]
    assert t.terrain_state.inert[1, 0] == pytest.approx(c, rel=1e-9)
    assert limits[10.0] < limits[1.0] < 2 * mass / (0.5 * c / 10.0)
    # the check treats the dampers as acting in every direction (conservative, docs/numerics.md): the plate's
    # bottom 1 mm below its CoM couples sliding with tilting, 14 % below the pure heave limit 2 m / c
    assert 0.8 * 2 * mass / c < limits[10.0] <= 2 * mass / c


def test_huge_timestep_warns():
    model, data = _plate(5.0, dt=0.05, mass=0.002)
    t = mjrft.GranularTerrain(model, medium="glass3_cp", resolution=0.004, inertial=True)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        t.step(data, 1)
    msgs = [str(r.message) for r in rec if issubclass(r.category, TerrainStabilityWarning)]
    assert msgs and "inertial-regime damping rate" in msgs[0]


def test_speed_range_extends_with_the_option():
    model, data = _plate(1.2)
    for inertial, warns in ((False, True), (True, False)):
        t = mjrft.GranularTerrain(model, medium="glass3_cp", resolution=0.004, inertial=inertial)
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always")
            t.step(data, 1)
        speed = [r for r in rec if issubclass(r.category, ValidityRangeWarning) and "speed" in str(r.message)]
        assert bool(speed) == warns
        mujoco.mj_resetData(model, data)
        data.qpos[2] = -0.003
        data.qvel[2] = -1.2
        mujoco.mj_forward(model, data)


def test_small_hexapod_scene_turns_it_on():
    from mjrft.models.hexapod import hexapod_xml

    small = mujoco.MjModel.from_xml_string(hexapod_xml(variant="small", medium="glass3_cp"))
    assert mjrft.GranularTerrain(small).inertial
    assert not mjrft.GranularTerrain(mujoco.MjModel.from_xml_string(hexapod_xml())).inertial
    assert not mjrft.GranularTerrain(mujoco.MjModel.from_xml_string(
        hexapod_xml(variant="small", inertial=False))).inertial
    # the scene's setting applies to its dry regions; with a wet law there is none, so nothing to turn on
    assert not mjrft.GranularTerrain(small, "sea_sand_saturated", "wet").inertial
