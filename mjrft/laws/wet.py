"""Saturated wet sand (SGRFT) and the free-water layer above it.

Source: "Granular Resistive Force Theory Extension for Saturated Wet Sand Ground" (Machines 10, 721,
2022), eqs. 6-9 and table 3. Two laws:

``wet`` (law id 3): the sand below the free surface
------------------------------------------------------
::

    sigma = sigma_base(beta, gamma, |z|) x factor(v)

``sigma_base`` is Li's RFT (:func:`mjrft.laws.rft.rft_stress`, the same maths and the medium's own
Fourier coefficients); ``v`` is the element's real speed (the ``speed`` argument, m/s), so the wet law
is rate-dependent where the dry laws are not.

Speed factor, the paper's linear velocity coefficient (eqs. 6-8)::

    factor(v) = 1 + eps_v (min(v, v_cap) - v_base) / dv

with eps_v = 0.16 per dv = 10 mm/s and v_base = 30 mm/s (table 3's base case). This is the paper's
own use of eps_v: "force and velocity are approximately linearly related, and the velocity
coefficient is the slope of the fitted line ... added as a multiplier" (section 3.1), every other
force is predicted from the base force at 30 mm/s and 30 mm depth, and the paper applies the SAME
line at leg speeds far above its 10-50 mm/s plate tests: its predicted +30.33 % horizontal thrust
from 30 to 40 rpm (section 3.2) is what this line gives on a 110 mm leg sunk 30 mm (the buried
part moves at 0.25-0.46 m/s; mjrft's rig gives +30.29 %, the ``sgrft_rpm`` validation case). Other
readings miss that number (evaluated by hand at one effective radius, 95-110 mm): the same line
anchored at 10 mm/s gives +28.6 to +28.9 %, force proportional to speed +33.3 %, compounding eps_v
per 10 mm/s ((1 + eps_v) ** ((v - v_base) / dv)) +340 to +450 %, and a factor held at its 50 mm/s
value +0 %.

What the line does not meet: the paper's plate ratio F(50 mm/s) / F(10 mm/s) = 1.786 at 30 mm depth
(section 2.4) becomes 1.32 / 0.68 = 1.94 (+8.7 %); eps_v is the paper's average over its test
depths, so one depth can differ, and the paper's own predictions err by up to 16 % and more at the
lowest speed and depth (fig. 6). The ``sgrft_plate_speed`` validation case reports it.

Limits (the paper states none; documented choices that apply to every scene):

* high speed: above ``v_cap`` = 1 m/s the factor is held at its value there (1 + 0.16 x 97 = 16.52
  with the default constants). 1 m/s is the speed up to which the dry RFT that SGRFT
  extends is stated rate-independent (the paper's introduction and section 3.1, citing Goldman and
  co-workers [10]); the paper offers no basis for its line beyond it. The hold keeps the force
  finite at any speed (1e300 m/s, inf), and the factor is continuous there.
* zero and low speed: the line is used down to v = 0, where it is 1 - eps_v v_base / dv = 0.52
  (finite and positive: an element at rest still resists with 0.52 of the base stress, direction
  from the unit motion m; the coupler's rest model decides what a resting element feels). A NaN or
  negative speed counts as 0.
* positivity: a line that would reach zero or below anywhere on [0, v_cap] (eps_v v_base / dv >= 1,
  or a negative eps_v steep enough to cross zero before v_cap) is rejected with a ValueError when
  the medium's parameters are built, so the factor is > 0 at every speed.

The plate tests' speed range 10-50 mm/s (``V_MIN``, ``V_MAX``; medium constants ``wet_v_min``,
``wet_v_max``) is the calibrated range of eps_v. It does not change the force; it is the range the
validity-range checks report against.

Medium constants (``Medium.extra``; defaults in parentheses, used by any medium that lacks them, so
``wet`` on e.g. ``poppy_cp`` is that medium's RFT times the SGRFT speed factor):
``wet_eps_v`` (0.16), ``wet_v_base`` (0.030 m/s), ``wet_dv`` (0.010 m/s), ``wet_v_cap`` (1.0 m/s),
``wet_v_min`` (0.010 m/s), ``wet_v_max`` (0.050 m/s). :func:`mjrft.tools.calibration.fit_wet_speed_coefficient`
fits eps_v the paper's way (a straight line of force per depth against speed).

Stress scale of the catalogue medium ``sea_sand_saturated`` (``mjrft.media``): table 3 gives
alpha^30 = 0.47 with no unit. We read it as the medium's scaling factor zeta at the 30 mm/s base
case, in Li's unit N/cm^3: the generic profile scaled to zeta = 0.47 N/cm^3 = 4.7e5 N/m^3 (so a
horizontal plate pushed down at 30 mm/s feels 0.47 N/cm^3 per depth, a vertical plate dragged
horizontally 0.370 x 0.47 = 0.174 N/cm^3). SGRFT writes sigma = sigma_base x eps_v with sigma_base
"the RFT base stress", and zeta is the one scalar that scales Li's base stress, hence this choice.
Table 3's alpha^10 = 0.23 and alpha^20 = 0.37 are not inputs: the law's stress per depth at 10
and 20 mm/s is alpha^30 x factor(v), 0.47 x 0.68 = 0.320 and 0.47 x 0.84 = 0.395 N/cm^3 (+39 % and
+6.7 %). Table 3 itself is not one line: alpha^30 / alpha^10 = 2.04 where eps_v gives 1 / 0.68 =
1.47, and it exceeds the 1.786 the paper measured between 10 and 50 mm/s. The ``sgrft_plate_depth``
validation case reports the comparison.

Dry reference (for "wet < dry below ~20 mm/s, > dry above ~30 mm/s"): the paper does not tabulate
its dry sand, so :func:`dry_reference` is the SAME sea sand dry, i.e. the generic profile with the
rate-independent stress that the wet law reaches at the middle of the paper's crossover band,
DRY_CROSSOVER_SPEED = 25 mm/s: zeta_dry = 0.47 x factor(25 mm/s) = 0.47 x 0.92 = 0.432 N/cm^3.
This is a stated assumption built from the paper's own crossover statement, not a measurement, so
"wet below dry at <= 20 mm/s, above at >= 30 mm/s" holds by construction (wet/dry 0.739 at 10,
0.913 at 20, 1.087 at 30 and 1.435 at 50 mm/s); what is not built in is the paper's other dry fact,
"no significant difference" between the media at 30 mm/s (fig. 3b): +8.7 %. (No Li catalogue
medium can serve: on a vertical plate dragged horizontally they give 0.083-0.137 N/cm^3, all below
the wet sand's 0.146 N/cm^3 at 20 mm/s, so wet would already beat them there.)

``water`` (law id 4): the free-water layer above the sand
----------------------------------------------------------
SGRFT: an element in the water layer (0 <= height above the sand < water depth) feels
F_w = C rho_w v^2 S, S its projected leading area; above the water, nothing. Per element::

    sigma = -C rho_w v^2 max(0, n . m) m     (n outward unit normal, m unit motion, v = speed)

so a face-on plate of area A feels C rho_w v^2 A and an edge-on one nothing. The paper's formula has
no 1/2, so C is half the textbook drag coefficient C_D: default C = 0.585 = 1.17 / 2, with
C_D = 1.17 the square flat plate normal to the flow (Hoerner, Fluid-Dynamic Drag, 1965; Re > 1e3;
at the paper's 30 mm/s on a 20 mm plate Re ~ 600, where C_D is still about 1.1-1.2).
Default rho_w = 1000 kg/m^3 (fresh water; the paper saturates the sand with water, not sea water).

Choices where the paper is silent (continuity, so a body crossing an interface feels no jump):

* the drag fades linearly to zero over a skin ``water_skin`` (default 1 mm = the sea sand's
  largest grain size) just below the water surface, so it is exactly zero at and above it;
* at the sand surface the drag does not stop: it fades out over the same skin INTO the sand
  (depth 0 -> skin), while the wet-sand stress grows from zero; the top grain layer is a slurry.
  Elements exactly at the sand surface (height 0) feel the full drag, as the paper's
  0 <= height says. A water layer thinner than the skin uses a skin of the layer's depth.
* ``water`` gives ONLY the water layer (zero deeper than the skin); a saturated ground with standing
  water is ``wet`` + ``water`` on the same element. ``depth`` is positive below the sand surface as
  in every law; the water layer has ``depth < 0`` (height = -depth). Buoyancy is not a drag and is
  not included.

Medium constants: ``water_depth`` (0 m: no layer; set it for your scene: the paper's test box had
the water 50 mm above the sand, its running experiments under 10 mm, sections 2.2 and 4.2), ``drag_coefficient`` (0.585), ``water_density`` (1000 kg/m^3), ``water_skin``
(1e-3 m).

Parameter slots (:mod:`mjrft.params`, from ``P_FIRST_FREE`` = 15): 15 eps_v / dv (s/m),
16 v_base, 17 v_cap (m/s), 18 factor(v_cap); 19 water depth (m), 20 C x rho_w (kg/m^3), 21 skin (m).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..errors import check_finite, check_positive
from ..media import N_CM3, generic
from ..params import (P_WATER_DEPTH, P_WATER_DRAG, P_WATER_SKIN, P_WET_FCAP, P_WET_K, P_WET_VBASE,
                      P_WET_VCAP)
from .rft import rft_stress

# --- SGRFT constants (table 3 and section 3 of the reference) ---------------------------------
EPS_V = 0.16  # velocity coefficient per DV (table 3)
V_BASE = 0.030  # base case speed, m/s (table 3)
DV = 0.010  # speed step of eps_v, m/s ("per 10 mm/s")
V_MIN = 0.010  # lowest plate-test speed, m/s: the calibrated range of EPS_V (no effect on the force)
V_MAX = 0.050  # highest plate-test speed, m/s
V_CAP = 1.0  # m/s: the factor is held above it (module docstring, "Limits")
ALPHA30 = 0.47  # table 3 alpha^30, read as zeta in N/cm^3 at V_BASE (module docstring)
DRY_CROSSOVER_SPEED = 0.025  # middle of the paper's 20-30 mm/s wet/dry crossover band, m/s

# --- water layer ------------------------------------------------------------------------------
WATER_DENSITY = 1000.0  # kg/m^3
DRAG_COEFFICIENT = 0.585  # C in C rho v^2 S = C_D / 2, C_D = 1.17 (square flat plate, Hoerner)
WATER_SKIN = 1e-3  # m, the sea sand's largest grain (grains <= 1 mm)



def speed_factor(v, eps_v=EPS_V, v_base=V_BASE, dv=DV, v_cap=V_CAP):
    """The SGRFT speed factor (numpy, broadcasts): ``1 + eps_v (min(v, v_cap) - v_base) / dv``.

    A NaN or negative speed counts as 0; ``v >= v_cap`` (also inf) gives the factor at ``v_cap``.
    """
    v = np.asarray(v, dtype=float)
    v = np.where(v > 0.0, np.minimum(v, v_cap), 0.0)  # NaN > 0 is False
    return 1.0 + eps_v * (v - v_base) / dv


@njit(cache=True, inline="always")
def wet_speed_factor(speed, p):
    if speed >= p[P_WET_VCAP]:  # also inf
        return p[P_WET_FCAP]
    v = speed if speed > 0.0 else 0.0  # NaN > 0 is False
    return 1.0 + p[P_WET_K] * (v - p[P_WET_VBASE])


@njit(cache=True)
def wet_stress(depth, nx, ny, nz, mx, my, mz, speed, p):
    """SGRFT stress (Pa): Li RFT of the medium x the speed factor of the element's speed (> 0, finite)."""
    sx, sy, sz = rft_stress(depth, nx, ny, nz, mx, my, mz, speed, p)
    if sx == 0.0 and sy == 0.0 and sz == 0.0:
        return 0.0, 0.0, 0.0
    f = wet_speed_factor(speed, p)
    return sx * f, sy * f, sz * f


@njit(cache=True)
def water_drag_stress(height_above_sand, water_depth, nx, ny, nz, mx, my, mz, speed, rho_w, c_d,
                      skin=WATER_SKIN):
    """Water-layer drag stress (Pa) on one element: ``-C rho_w v^2 max(0, n.m) m`` inside the layer.

    ``height_above_sand`` (m, negative below the sand surface), ``water_depth`` (m), ``n`` outward unit
    normal, ``m`` unit motion, ``speed`` (m/s), ``rho_w`` (kg/m^3), ``c_d`` the paper's C (no 1/2),
    ``skin`` (m) the fade length at both interfaces (see the module docstring).
    """
    if not (water_depth > 0.0) or not (skin > 0.0):
        return 0.0, 0.0, 0.0
    h = height_above_sand
    s = min(skin, water_depth)
    w = min((water_depth - h) / s, (h + s) / s)  # fade below the water surface / into the sand
    if not (w > 0.0):
        return 0.0, 0.0, 0.0
    if w > 1.0:
        w = 1.0
    proj = nx * mx + ny * my + nz * mz
    if proj <= 0.0:
        return 0.0, 0.0, 0.0
    k = -c_d * rho_w * speed * speed * proj * w
    return k * mx, k * my, k * mz


@njit(cache=True)
def water_stress(depth, nx, ny, nz, mx, my, mz, speed, p):
    """Law ``water``: the free-water layer for an element at ``depth`` (negative above the sand)."""
    return water_drag_stress(-depth, p[P_WATER_DEPTH], nx, ny, nz, mx, my, mz, speed, p[P_WATER_DRAG], 1.0,
                             p[P_WATER_SKIN])


def wet_constants(medium) -> dict:
    """The wet / water constants of ``medium`` (its ``extra`` values or the documented defaults), checked.

    Besides each value's own range, the speed factor's line must stay > 0 on [0, wet_v_cap] (module
    docstring, "Limits"); a ValueError names the medium, the constants and the speed where it fails.
    """
    g = medium.get
    name = getattr(medium, "name", "?")
    c = {
        "wet_eps_v": g("wet_eps_v", EPS_V),
        "wet_v_base": g("wet_v_base", V_BASE),
        "wet_dv": g("wet_dv", DV),
        "wet_v_cap": g("wet_v_cap", V_CAP),
        "wet_v_min": g("wet_v_min", V_MIN),
        "wet_v_max": g("wet_v_max", V_MAX),
        "water_depth": g("water_depth", 0.0),
        "drag_coefficient": g("drag_coefficient", DRAG_COEFFICIENT),
        "water_density": g("water_density", WATER_DENSITY),
        "water_skin": g("water_skin", WATER_SKIN),
    }
    for key in ("wet_v_base", "wet_v_min", "water_depth", "drag_coefficient", "water_density"):
        c[key] = check_positive(f"medium {name!r} {key}", c[key], allow_zero=True)
    for key in ("wet_dv", "wet_v_cap", "wet_v_max", "water_skin"):
        c[key] = check_positive(f"medium {name!r} {key}", c[key])
    c["wet_eps_v"] = check_finite(f"medium {name!r} wet_eps_v", c["wet_eps_v"])
    if c["wet_v_min"] > c["wet_v_max"]:
        raise ValueError(f"medium {name!r}: wet_v_min ({c['wet_v_min']!r}) must be <= wet_v_max ({c['wet_v_max']!r})")
    for v in (0.0, c["wet_v_cap"]):  # a line is smallest at an end of [0, v_cap]
        f = float(speed_factor(v, c["wet_eps_v"], c["wet_v_base"], c["wet_dv"], c["wet_v_cap"]))
        if not f > 0.0:
            raise ValueError(f"medium {name!r}: the wet speed factor 1 + wet_eps_v (v - wet_v_base) / wet_dv is "
                             f"{f:.4g} <= 0 at v = {v!r} m/s (wet_eps_v {c['wet_eps_v']!r}, wet_v_base "
                             f"{c['wet_v_base']!r}, wet_dv {c['wet_dv']!r}, wet_v_cap {c['wet_v_cap']!r}); it must "
                             f"be > 0 for every speed in [0, wet_v_cap]")
    return c


def wet_params(medium, p):
    """The wet law's and the water layer's constants of ``medium`` into its parameter vector ``p``."""
    c = wet_constants(medium)
    p[P_WET_K] = c["wet_eps_v"] / c["wet_dv"]
    p[P_WET_VBASE] = c["wet_v_base"]
    p[P_WET_VCAP] = c["wet_v_cap"]
    p[P_WET_FCAP] = 1.0 + p[P_WET_K] * (c["wet_v_cap"] - c["wet_v_base"])
    p[P_WATER_DEPTH] = c["water_depth"]
    p[P_WATER_DRAG] = c["drag_coefficient"] * c["water_density"]
    p[P_WATER_SKIN] = c["water_skin"]


def dry_reference(name: str = "sea_sand_dry_reference"):
    """The dry reference medium of the wet-vs-dry facts (module docstring): generic x 0.432 N/cm^3."""
    zeta = ALPHA30 * N_CM3 * float(speed_factor(DRY_CROSSOVER_SPEED))
    return generic.scaled(zeta, name=name)
