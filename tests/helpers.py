"""Helpers shared by the test modules (plain functions and constants; the fixtures are in conftest.py): bodies
pressed into the grains and stepped one at a time, as tests/mjrft/test_extremes.py and tests/mjrft/test_implicit_step.py
use them; the registration of the validation cases' tests (:class:`CaseTests`) and what they read from a case's
result, as the modules of tests/mjrft/tools/validation/ use them."""

from __future__ import annotations

import functools
import re
import warnings
from typing import Callable

import mujoco
import numpy as np
import pytest

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


# ------------------------------------------------------------------------------------------------
# validation cases (tests/mjrft/tools/validation/)
# ------------------------------------------------------------------------------------------------
class CaseTests:
    """The tests of the validation cases of one test module (``test_validation_<case module>.py``), registered by the
    case's name in three tables, each run by one test parametrised over them (pytest ids are the case names):

    * :meth:`outcome`: what the case's quick run must show: its published qualitative outcomes and the numbers the
      test pins (``test_case[name]``);
    * :meth:`disagreement`: the published outcomes mjrft does not reproduce, strict expected failures that carry the
      measured cause (``test_known_disagreement[name]``);
    * :meth:`control`: a wrong-physics control (a rigid floor, the law that distinguishes what the paper calls
      similar, a start that flips the robot) that a check of the case must reject, run through the case's own check
      functions (``test_control[name: control]``).

    The module ends with ``test_case, test_known_disagreement, test_control = case_tests.runners()`` (an empty table
    gives None, which pytest does not collect). The quick run of a case is the session fixture ``quick_run``."""

    def __init__(self):
        self.outcomes: dict[str, object] = {}  # case -> its outcome test (a function of the quick result)
        self.disagreements: dict[str, object] = {}  # case -> the outcomes it does not reproduce (strict xfail)
        self.controls: dict[str, object] = {}  # "case: control" -> a check run on a wrong-physics control

    def outcome(self, name: str, slow: bool = False):
        """Register ``check(result)`` as the outcome test of case ``name``."""
        def register(check: Callable):
            assert name not in self.outcomes, name
            self.outcomes[name] = pytest.param(name, check, id=name, marks=[pytest.mark.slow] if slow else [])
            return check
        return register

    def disagreement(self, name: str, reason: str, slow: bool = False):
        """Register ``check(result)`` as the published outcomes of case ``name`` that mjrft does not reproduce: a
        strict xfail with the measured cause as its reason."""
        def register(check: Callable):
            assert name not in self.disagreements, name
            marks = [pytest.mark.xfail(strict=True, reason=reason)] + ([pytest.mark.slow] if slow else [])
            self.disagreements[name] = pytest.param(name, check, id=name, marks=marks)
            return check
        return register

    def control(self, name: str, what: str, slow: bool = False, marks: tuple = ()):
        """Register ``check()`` as a wrong-physics control (``what``) that a check of case ``name`` must reject."""
        def register(check: Callable):
            key = f"{name}: {what}"
            assert key not in self.controls, key
            self.controls[key] = pytest.param(check, id=key, marks=[*marks, *([pytest.mark.slow] if slow else [])])
            return check
        return register

    def runners(self) -> tuple:
        """``(test_case, test_known_disagreement, test_control)`` over this module's tables (None where empty)."""
        def test_case(name, check, quick_run):
            """The case's quick run shows its published outcomes (and the numbers its test pins)."""
            check(quick_run(name))

        def test_known_disagreement(name, check, quick_run):
            """The published outcomes the case does not reproduce (strict xfail: one that starts to agree is
            reported)."""
            check(quick_run(name))

        def test_control(check):
            """A check of the case rejects a wrong-physics control (and, where stated, accepts the case's own
            physics)."""
            check()

        def over(table: dict, argnames: str, test):
            return pytest.mark.parametrize(argnames, list(table.values()))(test) if table else None

        return (over(self.outcomes, "name, check", test_case),
                over(self.disagreements, "name, check", test_known_disagreement),
                over(self.controls, "check", test_control))


def published_outcomes(result) -> dict:
    """Every published outcome of a case's ``result`` holds (and it has some); its checks by name."""
    assert result.outcomes and not result.failed_outcomes, (result.name, result.failed_outcomes)
    return result.by_name


def named_checks(result, names) -> list:
    """The checks of ``result`` named in ``names``; ``*`` in a name stands for any text (each name must match one)."""
    out = []
    for n in names:
        pattern = re.compile(".*".join(re.escape(part) for part in n.split("*")))
        hit = [c for c in result.checks if pattern.fullmatch(c.name)]
        assert hit, (result.name, n, [c.name for c in result.checks])
        out += hit
    return out


@functools.lru_cache(maxsize=None)
def variant_run(name: str, variant: str):
    """Case ``name`` at its quick settings under the wrong-physics ``variant`` (run once per session)."""
    from mjrft.tools import validation

    return validation.run_case(name, quick=True, variant=variant)
