"""Air fluidisation of the bed (mjrft.media.fluidized): an upward air flow carrying a share of the grains' weight
weakens every frictional stress by the same share, leaves grain inertia alone, and is refused at the onset."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mjrft
from mjrft import laws
from mjrft.laws.inertial import set_inertial
from mjrft.laws.registry import parameter_vector
from mjrft.params import P_INERTIA

DEPTH = np.array([0.02, 0.05])
NORMAL = np.array([[0.0, 0.0, -1.0], [0.6, 0.0, -0.8]])
VELOCITY = np.array([[0.0, 0.0, -0.01], [0.01, 0.0, -0.005]])
AREA = np.array([1e-4, 2e-4])


@pytest.mark.parametrize("law", ["rft", "rft3d", "depth_only"])
def test_frictional_stresses_carry_the_air_share_of_the_weight(law):
    """With the air carrying 40 % of the grains' weight every dry law's force is 0.6 of the still bed's (the
    effective stress). Control: the still bed's force is not (a ratio of 1)."""
    still = getattr(laws, law)(DEPTH, NORMAL, VELOCITY, AREA, "poppy_lp")
    air = getattr(laws, law)(DEPTH, NORMAL, VELOCITY, AREA, mjrft.fluidized("poppy_lp", 0.4))
    np.testing.assert_allclose(air, 0.6 * still, rtol=1e-9, atol=1e-15)
    assert not np.allclose(still, 0.6 * still)


def test_grain_inertia_and_the_state_stay():
    """The inertial regime's C rho_bulk (grain inertia), the packing and the angle of repose are the still bed's;
    the onset of fluidisation (the air carrying the whole weight) and beyond are refused; flows compose."""
    base = mjrft.get_medium("glass3_cp")
    air = mjrft.fluidized(base, 0.5)
    p0, p1 = parameter_vector(base), parameter_vector(air)
    set_inertial(p0, base, 2.2)
    set_inertial(p1, air, 2.2)
    assert p1[P_INERTIA] == p0[P_INERTIA] > 0
    assert (air.volume_fraction, air.repose_angle, air.grain_density) == (0.63, 21.0, 2600.0)
    assert math.isclose(mjrft.fluidized(air, 0.5).zeta, 0.25 * base.zeta) and mjrft.fluidized(air, 0.5).name == \
        "glass3_cp@air0.75"
    assert mjrft.fluidized(base, 0.0) is base
    for bad in (1.0, 1.5, -0.1, float("nan")):
        with pytest.raises(ValueError, match="air_flow"):
            mjrft.fluidized(base, bad)


def test_a_fluidised_bed_keeps_its_packing_pair():
    """The ground memory of a fluidised medium moves between its base pair's states under the same flow."""
    from mjrft.ground import packing_of

    p = packing_of(mjrft.fluidized("poppy_cp", 0.3))
    assert (p.loose.name, p.close.name) == ("poppy_lp@air0.3", "poppy_cp@air0.3")
    assert math.isclose(p.loose.zeta, 0.7 * mjrft.get_medium("poppy_lp").zeta)


def test_a_loaded_foot_sinks_deeper_the_higher_its_pressure():
    """A foot resting on a fluidised bed sinks to the depth where the weakened stress carries its pressure, so the
    extra sinkage an air flow adds grows with the foot pressure (the thesis, sec. 1.4.3 and fig. 4: the performance
    loss on the fluidised bed grows with the foot pressure mg / nA). Measured on two plates settling under 0.5 and
    2 kPa on loosely packed poppy seeds, still and at half the onset. Control: a flow that weakens nothing (the still
    bed twice) adds no sinkage and fails the check."""
    import mujoco

    xml = """<mujoco><option timestep="0.0005"/><worldbody><body pos="0 0 0.01"><freejoint/>
    <geom type="box" size="0.02 0.02 0.003" mass="{m}"/></body></worldbody></mujoco>"""
    sink = {}
    for pressure in (500.0, 2000.0):
        mass = pressure * 0.04 * 0.04 / 9.81
        for flow in (0.0, 0.5):
            model = mujoco.MjModel.from_xml_string(xml.format(m=mass))
            data = mujoco.MjData(model)
            t = mjrft.GranularTerrain(model, mjrft.fluidized("poppy_lp", flow), "rft", resolution=0.005)
            t.step(data, 3000)
            sink[pressure, flow] = t.sinkage().max()

    def grows_with_pressure(extra):
        return extra[2000.0] > 2.0 * extra[500.0] > 1e-4

    assert grows_with_pressure({p: sink[p, 0.5] - sink[p, 0.0] for p in (500.0, 2000.0)})
    assert not grows_with_pressure({p: sink[p, 0.0] - sink[p, 0.0] for p in (500.0, 2000.0)})
