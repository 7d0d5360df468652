"""Calibrated ranges of the laws (mjrft.laws.validity) and GranularTerrain's once-per-terrain warnings."""

import dataclasses
import warnings

import mujoco
import pytest

import mjrft
from mjrft.coupler import GranularTerrain
from mjrft.laws import LAW_IDS
from mjrft.laws.registry import LAWS
from mjrft.laws.validity import check_static
from mjrft.media import MEDIA

BOX = """<mujoco><option timestep="0.001"/><worldbody><body name="foot" pos="0 0 0.02"><freejoint/>
<geom type="box" size="0.02 0.02 0.01" mass="0.5"/></body></worldbody></mujoco>"""


def _drag(medium, law, z, vx, steps=120):
    """Hold a box with its centre at height z moving at vx along x for ``steps`` evaluations; the warnings."""
    m = mujoco.MjModel.from_xml_string(BOX)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        t = GranularTerrain(m, medium, law)
        d = mujoco.MjData(m)
        for _ in range(steps):
            d.qpos[:3] = (0.0, 0.0, z)
            d.qvel[:] = 0.0
            d.qvel[0] = vx
            mujoco.mj_forward(m, d)
            t.compute(d)
            d.time += m.opt.timestep
    return [str(w.message) for w in rec if issubclass(w.category, mjrft.ValidityRangeWarning)]


BIG_GRAINS = dataclasses.replace(MEDIA["poppy_cp"], name="pebbles", grain_diameter=5e-3)
LOOSE_3D = mjrft.medium_3d("light", 1000.0, 0.5, 0.3)
SLIPPERY_3D = mjrft.medium_3d("slippery", 1500.0, 0.1, 0.3)


@pytest.mark.parametrize("medium, law, z, vx, expect", [
    ("poppy_cp", "rft", -0.10, 0.1, ["law 'rft'", "depth 11 cm", "<= 9.525 cm", "Li 2013"]),
    ("poppy_cp", "rft", -0.02, 2.0, ["law 'rft'", "speed 2 m/s", "<= 1 m/s"]),
    (BIG_GRAINS, "rft", -0.02, 0.1, ["law 'rft'", "grain diameter 5 mm", "0.1 to 3.2 mm", "'pebbles'"]),
    ("poppy_cp", "depth_only", -0.10, 0.1, ["law 'depth_only'", "depth 11 cm", "<= 9.525 cm"]),
    ("sea_sand_saturated", "wet", -0.02, 0.3, ["law 'wet'", "speed 300 mm/s", "<= 50 mm/s", "SGRFT"]),
    ("sea_sand_saturated", "wet", -0.08, 0.03, ["law 'wet'", "depth 90 mm", "<= 70 mm"]),
    ("poppy_cp", "hybrid", -0.06, 0.1, ["law 'hybrid'", "depth 7 cm", "<= 4 cm"]),
    ("poppy_cp", "hybrid", -0.02, 1.5, ["law 'hybrid'", "speed 1.5 m/s", "<= 1 m/s"]),
    (LOOSE_3D, "rft3d", -0.02, 0.1, ["law 'rft3d'", "bulk density 1e+03 kg/m^3", "1310 to 1700 kg/m^3"]),
    (SLIPPERY_3D, "rft3d", -0.02, 0.1, ["law 'rft3d'", "internal friction 0.1", "0.21 to 1.07"]),
    ("glass3_cp", "rft3d", -0.02, 3.0, ["law 'rft3d'", "speed 3 m/s", "<= 1 m/s"]),
])
def test_leaving_a_range_warns_once_naming_law_quantity_value_and_range(medium, law, z, vx, expect):
    msgs = _drag(medium, law, z, vx, steps=200)
    assert len(msgs) == 1, msgs
    for text in expect:
        assert text in msgs[0], (text, msgs[0])


@pytest.mark.parametrize("medium, law", [("poppy_cp", "rft"), ("glass03_lp", "depth_only"), ("glass3_cp", "rft3d"),
                                         ("sea_sand_saturated", "wet"), ("poppy_cp", "hybrid")])
def test_inside_every_range_nothing_warns(medium, law):
    vx = 0.03 if law == "wet" else 0.2
    assert _drag(medium, law, -0.015, vx, steps=200) == []


def test_two_quantities_warn_once_each_and_a_second_terrain_warns_again():
    msgs = _drag("poppy_cp", "rft", -0.10, 2.0, steps=300)
    assert len(msgs) == 2 and any("depth" in m for m in msgs) and any("speed" in m for m in msgs)
    assert len(_drag("poppy_cp", "rft", -0.10, 0.1)) == 1


def test_every_law_has_ranges_and_the_tables_media_are_inside_li_grain_range():
    assert {law.name for law in LAWS if law.ranges} == set(LAW_IDS) - {"water"}  # the water layer's drag: none
    for name in ("poppy_lp", "poppy_cp", "glass03_lp", "glass03_cp", "glass3_cp"):
        assert check_static("rft", MEDIA[name]) == []
    assert check_static("wet", MEDIA["sea_sand_saturated"]) == []


def test_hexapod_default_scene_warns_only_that_its_legs_pass_li_speed_bound():
    """Under its 2 Hz tripod the default hexapod's fastest buried leg element briefly passes Li 2013's 1 m/s
    (measured 1.04 m/s); nothing else leaves a range."""
    import gymnasium

    from mjrft.tools.gaits import make_gait

    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", mjrft.ValidityRangeWarning)
        env = gymnasium.make("mjrft/HexapodSand-v0")
        pol = make_gait("tripod", env.unwrapped)
        obs, _ = env.reset(seed=0)
        while env.unwrapped.data.time < 2.0:
            obs, *_ = env.step(pol.predict(obs)[0])
        env.close()
    msgs = [str(w.message) for w in rec if issubclass(w.category, mjrft.ValidityRangeWarning)]
    assert len(msgs) <= 1, msgs
    for m in msgs:
        assert "law 'rft': speed 1.0" in m and "<= 1 m/s" in m, m


def test_the_saturated_law_on_a_dry_medium_is_named_once():
    import warnings

    import mujoco

    m = mujoco.MjModel.from_xml_string('<mujoco><worldbody><body pos="0 0 0.1"><freejoint/>'
                                       '<geom type="box" size=".05 .05 .01" mass="1"/></body></worldbody></mujoco>')
    for medium, expected in (("poppy_cp", 1), ("sea_sand_saturated", 0)):  # control: the medium SGRFT measured
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            GranularTerrain(m, medium, "wet", resolution=0.01)
        notes = [str(w.message) for w in caught if "saturated-sand calibration" in str(w.message)]
        assert len(notes) == expected, notes
        if expected:
            assert f"medium '{medium}'" in notes[0] and "'sea_sand_saturated'" in notes[0]
