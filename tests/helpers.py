"""Helpers shared by the test modules (plain functions and constants; the fixtures are in conftest.py): bodies
pressed into the grains and stepped one at a time, as tests/mjrft/test_extremes.py and tests/mjrft/test_implicit.py
use them."""

from __future__ import annotations

import warnings

import mujoco
import numpy as np

import mjrft
from mjrft.media import MEDIA

G = 9.81
LAWS = ("rft", "rft3d", "depth_only")
POPPY = MEDIA["poppy_cp"]
MEDIA_X = {  # poppy seeds, 10x softer and 10x stiffer
    "soft": POPPY.scaled(0.1 * POPPY.zeta, name="poppy_soft"),
    "poppy": POPPY,
    "stiff": POPPY.scaled(10.0 * POPPY.zeta, name="poppy_stiff"),
}
LEG = 0.041  # RHex leg chord 2R' (m): "far below" is 10 legs deep


def enough(steps: int) -> int:
    """At least ``steps``, and long enough for two stability checks (they run every few hundred steps)."""
    return max(steps, 2 * mjrft.coupler.STABILITY_CHECK_EVERY + 1)


BOX = """<mujoco><option timestep="{dt}" integrator="{integrator}"/><worldbody>
<body name="foot" pos="0 0 {z}"><freejoint/><geom name="plate" type="box" size="{hx} {hx} {hz}" mass="{mass}"/></body>
</worldbody></mujoco>"""

ROD = """<mujoco><option timestep="{dt}"/><worldbody>
<body name="rod" pos="0 0 {top}"><joint name="hinge" type="hinge" axis="0 1 0"/>
<geom name="bar" type="box" pos="0 0 -{half}" size="0.0015 0.005 {half}" mass="{mass}"/></body>
</worldbody></mujoco>"""


def plate(mass=1.0, hx=0.05, hz=None, dt=1e-3, bottom=0.0, integrator="Euler"):
    """A free box plate whose bottom face is ``bottom`` metres below the surface z = 0."""
    hz = hx / 4 if hz is None else hz
    m = mujoco.MjModel.from_xml_string(BOX.format(dt=dt, z=hz - bottom, hx=hx, hz=hz, mass=mass,
                                                  integrator=integrator))
    m.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
    return m, mujoco.MjData(m)


def settled_depth(mass, hx, medium):
    """Slowly loaded flat plate: load / (alpha_z(0, pi/2) x area)."""
    return mass * G / (medium.alpha_z_down * (2 * hx) ** 2)


def energy(m, d) -> float:
    """Kinetic + potential energy of the current state (mj_forward computes it with mjENBL_ENERGY)."""
    mujoco.mj_forward(m, d)
    return float(d.energy[0] + d.energy[1])


def assert_finite(d, t):
    for name, arr in (("qpos", d.qpos), ("qvel", d.qvel), ("force", t.force), ("wrench", t.wrench),
                      ("depth", t.depth), ("xfrc_applied", d.xfrc_applied)):
        assert np.all(np.isfinite(arr)), f"non-finite {name}"


def run(m, d, t, steps):
    """Step one at a time; returns (energy before each step and after the last, stability warnings).

    ``d.energy`` (mjENBL_ENERGY) is computed by each step's mj_step1: the state the step starts from. A run that
    diverges (NonFiniteError) after the terrain warned ends there; one that diverges without a warning fails."""
    energies = [energy(m, d)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", mjrft.TerrainStabilityWarning)
        try:
            for k in range(steps):
                t.step(d)
                assert_finite(d, t)
                if k:
                    energies.append(float(d.energy[0] + d.energy[1]))
            energies.append(energy(m, d))
        except mjrft.NonFiniteError:
            if not any(issubclass(w.category, mjrft.TerrainStabilityWarning) for w in caught):
                raise
    warned = [w for w in caught if issubclass(w.category, mjrft.TerrainStabilityWarning)]
    return np.array(energies), warned


def turn_number(medium, mass, hx, bottom, speed, dt):
    """Velocity change of a first step relative to the speed: the plate's yield force (alpha_z(0, pi/2)
    x depth x bottom area; lift is of that size) x dt / (m max(|v|, delta / tau)); below delta / tau =
    0.2 m/s the element memory, not the direction of motion, sets the force."""
    force = medium.alpha_z_down * max(bottom, 0.0) * (2 * hx) ** 2
    return force * dt / (mass * max(speed, 1e-3 / 0.0050))


def chatter(make, dt, seconds=0.3):
    """RMS velocity over the second half of a run, and whether the terrain warned."""
    m, d, t = make(dt)
    steps = enough(int(round(seconds / dt)))
    qv = np.empty((steps, m.nv))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", mjrft.TerrainStabilityWarning)
        for k in range(steps):
            t.step(d)
            qv[k] = d.qvel
    assert_finite(d, t)
    return float(np.sqrt(np.mean(qv[steps // 2:] ** 2))), bool(caught)


def hinged_leg(dt, implicit=False):
    """A 2 g leg on a frictionless hinge, its lower 2 cm pushed into the grains: its buried tip is
    three times lighter than its centre of mass, which the check must take into account."""
    m = mujoco.MjModel.from_xml_string(ROD.format(dt=dt, top=LEG - 0.02, half=LEG / 2, mass=0.002))
    d = mujoco.MjData(m)
    d.qpos[0], d.qvel[0] = 0.02, -1.0
    return m, d, mjrft.GranularTerrain(m, POPPY, "rft", resolution=0.0015, implicit=implicit)
