"""The dry inertial (speed-dependent) regime: an option of the dry laws ``rft``, ``rft3d`` and ``depth_only``.

Source: Zhang, Qian, Li, Masarati, Hoover, Birkmeyer, Pullin, Fearing & Goldman, "Ground fluidization
promotes rapid running of a lightweight robot", IJRR 2013 (DynaRoACH), sec. 3.2. Below a critical
intrusion speed ``v_c ~ sqrt(2 g d)`` (d the grain diameter; "for 3 mm glass particles, v_c = 25 cm/s")
grains resist with the rate-independent
yield stress that RFT fits; above it "the inertial force of the grains being accelerated by the legs
becomes important" and the force is "hydrodynamic-like", rising "approximately quadratically with
impact speed" (fig. 5: lift on a tripod ``F_z / mg = alpha v^2 + 1``, the 1 from the yield stress).

Model (added to the quasi-static law's force on every buried element; off by default)::

    u   = v . n                                   normal speed of the face into the grains (n outward)
    P   = C rho_bulk (u^2 - v_c^2)   if u > v_c,  else 0
    F   = -min(1, depth / skin) P A n

* Newtonian drag on the leading projected area: a face pushed along its normal at speed v feels
  ``C rho v^2 A`` (the granular counterpart of the water layer's ``C rho_w v^2 S``, mjrft.laws.wet);
  a face met at an angle feels its normal speed squared along its normal (only leading faces, u > 0).
* Choice: it applies above v_c and is continuous there (``u^2 - v_c^2``), so the regime starts at
  the paper's critical speed without a jump; at the fit's top speed (1 m/s) this is 6 % below a pure
  ``C rho u^2``.
* Choice: ``rho_bulk`` = grain density x volume fraction (the mass of grains set moving per swept
  volume); ``v_c = sqrt(2 g d)`` from the medium's grain diameter (:attr:`mjrft.media.Medium.critical_speed`;
  3.2 mm glass of Li's table S1: 25.1 cm/s, the paper's 25 cm/s). A medium without grain diameter or
  bulk density cannot use the option (ValueError).
* Choice (numerical, not physics): the pressure ramps in over ``INERTIAL_SKIN`` = 1 mm of depth below
  the surface (the water layer's skin), so an element crossing the surface at speed does not receive
  the whole impact pressure in one step.

The coefficient ``C`` (``INERTIAL_DRAG``, the same for every medium and scene). The seed paper states
three mutually consistent numbers for 12 Hz: the maximum vertical leg penetration speed "reached
nearly 1 m/s" (fig. 4B text), the peak vertical force on a tripod rose "to ~6-7 mg" (fig. 2J text),
and the speed passes v_c = 25 cm/s near 6 Hz. With the robot's mass m = 25 g, the paper's glass
(2.47 g/cm^3 at volume fraction 0.63: rho_bulk = 1556 kg/m^3) and the legs' projected area "~1.4 cm^2"
each (three per tripod), the tripod's inertial lift at that point gives

    C = m g (F_peak / mg - 1) / (rho_bulk 3 A_leg (v_max^2 - v_c^2))
      = 0.245 N x (6.5 - 1) / (1556 kg/m^3 x 4.2e-4 m^2 x (1.0 - 0.0625) m^2/s^2) = 2.20.

The fit printed in fig. 5's caption, ``alpha = 5.7e-3 cm^-2 s^2``, is not consistent with those
numbers: at 1 m/s it gives ``F_z / mg = 58``, nine times the stated peak (the stated peak needs
alpha ~ 5.5e-4 cm^-2 s^2). Taken literally it would give C = 21.4. We take C from the three
consistent statements; the validation case ``dynaroach_intrusion`` shows both against mjrft.

Stability (explicit integration). The pressure depends on velocity, so each element is a damper along
its normal, ``c = dF/du = 2 w C rho_bulk A u`` (w the skin ramp). On an effective mass ``m`` a damper is
stable under MuJoCo's semi-implicit Euler step iff ``c dt / m < 2``, i.e.

    dt < m / (w C rho_bulk A u).

The coupler's stability check includes it (:mod:`mjrft.stability`): the kernel sums the dampers' moments
about each body's CoM like the stiffness moments, and the check combines the stiffest spring mode with
the largest damping rate, a conservative bound. For a DynaRoACH leg (tip effective mass ~3 g through its
hip armature, 0.5 cm^2 buried, 1.5 m/s) the limit is ~10 ms, far above the 1 ms step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..errors import check_positive
from ..media import get_medium
from ..params import P_INERTIA, P_INERTIA_SKIN, P_INERTIA_VC2

# --- the coefficient and its source numbers (module docstring) --------------------------------
ROBOT_MASS = 0.025  # kg, DynaRoACH (abstract, sec. 2.1.1)
PEAK_LIFT = 6.5  # F_z / mg on a tripod at 12 Hz: "~6-7 mg" (sec. 3.2, fig. 2J text), the middle
PEAK_SPEED = 1.0  # m/s, maximum vertical leg penetration speed at 12 Hz: "nearly 1 m/s" (fig. 4B text)
PAPER_VC = 0.25  # m/s, v_c for 3 mm glass (sec. 3.2)
PAPER_RHO_BULK = 2470.0 * 0.63  # kg/m^3: glass 2.47 g/cm^3 (sec. 2.1.2) at volume fraction 0.63
LEG_AREA = 1.4e-4  # m^2, projected area of one leg (sec. 3.2: "~1.4 cm^2")
TRIPOD_AREA = 3 * LEG_AREA
INERTIAL_DRAG = (ROBOT_MASS * 9.81 * (PEAK_LIFT - 1.0)
                 / (PAPER_RHO_BULK * TRIPOD_AREA * (PEAK_SPEED ** 2 - PAPER_VC ** 2)))  # C = 2.20
INERTIAL_SKIN = 1e-3  # m (module docstring: numerical ramp below the surface)


def inertial_constants(medium, drag: float = INERTIAL_DRAG, skin: float = INERTIAL_SKIN) -> tuple[float, float, float]:
    """(C rho_bulk, v_c^2, skin) of ``medium`` for the parameter slots; ValueError when the medium lacks
    the grain diameter or the bulk density the regime needs, or ``drag`` / ``skin`` are not positive."""
    med = get_medium(medium)
    drag = check_positive("inertial_drag", drag)
    skin = check_positive("inertial skin", skin)
    if med.rho_bulk is None:
        raise ValueError(f"medium {med.name!r} has no grain density and volume fraction, so no bulk density for "
                         "the inertial regime (C rho_bulk v^2); give it grain_density and volume_fraction, or turn "
                         "inertial off")
    vc = med.critical_speed
    if vc is None:
        raise ValueError(f"medium {med.name!r} has no grain diameter, so no critical speed v_c = sqrt(2 g d) for the "
                         "inertial regime; give it grain_diameter, or turn inertial off")
    return drag * med.rho_bulk, vc * vc, skin


def set_inertial(p: np.ndarray, medium, drag: float = INERTIAL_DRAG) -> np.ndarray:
    """Write the inertial constants of ``medium`` into the parameter vector ``p`` (turns the regime on)."""
    p[P_INERTIA], p[P_INERTIA_VC2], p[P_INERTIA_SKIN] = inertial_constants(medium, drag)
    return p


@njit(cache=True, error_model="numpy", inline="always")
def inertial_force(p, depth, nx, ny, nz, vx, vy, vz, area):
    """Inertial force (N) on one element and its damping ``dF/du`` (N s/m) along the normal: (fx, fy, fz, c).

    ``n`` the unit outward normal, ``v`` the element's real velocity (m/s), ``depth`` > 0 below the
    surface. Zero when the regime is off (``p[P_INERTIA] = 0``), above the surface, or when the face's
    normal speed is at most v_c."""
    cr = p[P_INERTIA]
    u = vx * nx + vy * ny + vz * nz
    if cr <= 0.0 or depth <= 0.0 or u * u <= p[P_INERTIA_VC2] or u <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    w = min(1.0, depth / p[P_INERTIA_SKIN])
    k = w * cr * area
    f = k * (u * u - p[P_INERTIA_VC2])
    return -f * nx, -f * ny, -f * nz, 2.0 * k * u


@njit(cache=True, error_model="numpy")
def add_inertial(depth, normal, velocity, area, p, out):
    """Add the inertial forces of every element to ``out`` (n, 3) (the pure-law path; normals normalised here)."""
    for i in range(depth.shape[0]):
        nx, ny, nz = normal[i, 0], normal[i, 1], normal[i, 2]
        nl = math.sqrt(nx * nx + ny * ny + nz * nz)
        if nl == 0.0:
            continue
        fx, fy, fz, _ = inertial_force(p, depth[i], nx / nl, ny / nl, nz / nl, velocity[i, 0], velocity[i, 1],
                                       velocity[i, 2], area[i])
        out[i, 0] += fx
        out[i, 1] += fy
        out[i, 2] += fz
    return out
