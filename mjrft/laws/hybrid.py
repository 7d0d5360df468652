"""Hybrid force model for curved legs (Coulomb wedge + bar-drag fit), MuJoCo-free.

Source: "A hybrid force model to estimate the dynamics of curved legs in granular material" (the
hybrid paper), secs. 2.2-2.5 and 4. A leg (a curve in the vertical x-z plane of the rig,
z up, sand surface at z = 0) is cut into elements of length dl; each buried element gets a force per
unit leg length along its normal (F_perp) and along its tangent (F_par) that depend on psi (the angle
between its velocity and its tangent, 0..90 deg) and its depth d; summing gives the forward force
F_f, the support force F_s and the torque T.

What is implemented, and every choice where the paper is ambiguous
-------------------------------------------------------------------
1. **C_perp(d), Coulomb wedge** (:func:`wedge_force`), per unit bar length, for a bar of width h0
   whose top edge is at depth h1, bulk unit weight gamma_s, friction angles phi (internal) and phi_w
   (sand-bar)::

       W1 = gamma_s/2 h1^2 cot a1,   W2 = gamma_s/2 ((h0 + h1)^2 cot a2 - h1^2 cot a1)
       f(a1) = cot a1 / (tan phi + cot(a1 - phi)),   a1 = a_max = atan(tan phi + sec phi / sqrt 2)
       P  = gamma_s h1^2 f(a1) / (2 cos phi),   X1 = gamma_s h1^2 f(a1) / (2 sin(a1 - phi))
       P_w = [W2 sin(a2 + phi) + X1 sin(a2 - a1 + 2 phi)] / cos(phi_w + a2 + phi),   a2 = a_min
       C_perp = F_w = P_w cos phi_w

   a_min makes P_w stationary; P_w -> +inf at both ends of (0, pi/2 - phi - phi_w), so the stationary
   point is the minimum (the passive failure), found numerically (a 512-point grid then a golden
   section, plain numpy). With h1 = 0 this is exactly Coulomb's passive earth pressure (tested:
   2 F_w / (gamma_s h0^2) = K_p cos phi_w = 7.822 for phi = 35, phi_w = 20 deg).

   *Bar <-> leg element.* The bar width h0 is the leg's width W (the bar-drag bars are taken to have
   the leg's cross-section). An element at depth d is taken as the BOTTOM strip of such a bar: its
   buried face spans [max(0, d - W), d], i.e. h1 = max(0, d - W) and the face height is min(d, W).
   Reason: it uses the paper's formulas unchanged once d >= W, never counts sand above the surface,
   and makes C_perp(0) = 0, so the force is continuous when an element enters the sand (a top-edge or
   centre convention would make it jump by ~K_p gamma_s W^2 / 2 per metre of leg at d = 0).
   Because every term scales as gamma_s x length^2, C_perp(d) = gamma_s W^2 G(x), x = (d - W)/W, with
   G depending on phi and phi_w only: G is tabulated at set-up on x in [0, 40] (161 points, exact
   wedge, cached per (phi, phi_w)) and fitted by a least-squares quadratic G ~ g0 + g1 x + g2 x^2
   (g0 exact), within 0.05 % of the table for the defaults (tested). The numpy model uses the
   quadratic plus the linearly interpolated residual of the table (so it is exact at the nodes and
   within 1e-5 between them; the residual is held beyond x = 40); the compiled per-element law
   stores only g0, g1, g2 (a parameter vector has no room for a table).
   For d <= W, C_perp = gamma_s g0 d^2 exactly (h1 = 0, homogeneous of degree 2).

2. **Bar-drag fit** (:class:`HybridModel`), the paper's eqs. (3) and (4)::

       F_perp = C_perp^h + (C_perp - C_perp^h) sin psi
       F_par  = C_par^h + (C' - C_par^h) sin psi        psi <= 36 deg (region I)
       F_par  = C' cos psi                               psi >  36 deg (region II)
       C' = C_par / cos 36deg,   C_par = 0.37 C_perp

   The paper names C_par "the maximum F_par can reach, which occurs at 36 deg" (and measures
   C_par / C_perp = 0.37 +- 0.02 as a ratio of maxima), but writes region II as "C_par cos psi",
   which reaches C_par only at psi = 0, outside region II. We keep both of eq. (4)'s functional
   forms and give them the amplitude C' that makes region II reach the stated maximum C_par at the
   region boundary 36 deg. A force is continuous in psi, so region I must meet region II there:
   C_par^h + (C' - C_par^h) sin 36 = C_par, which fixes the psi = 0 value

       C_par^h = C_par (cos 36 - sin 36) / (cos 36 (1 - sin 36)) = 0.6634 C_par   (C_PAR_H_FRACTION)

   (region I is then C_par^h + (C_par - C_par^h) sin psi / sin 36). The paper gives no value of
   C_par^h beyond "depth dependent"; this one follows from its equations alone, and it agrees with
   its description of fig. 3e: F_par "increases slowly" in region I (by 0.34 C_par over 36 deg) and
   "decreases more rapidly" in region II (by C_par over 54 deg), which any C_par^h below C_par / 3
   would contradict. *C_perp^h* (psi = 0, the bar sliding along its own axis) has no such
   constraint; the default is 0, the paper's own explanation of fig. 3d (F_perp grows with psi
   "for the bar needed to push away more sand blocking its way"; at psi = 0 it blocks none).
   Measured values replace both through :func:`mjrft.tools.calibration.fit_hybrid_constants` /
   :meth:`HybridModel.from_fit`, or ``c_perp_h_coef`` / ``c_par_h_coef`` (N/m^3: C^h = coef x d x W).

3. **Only elements moving into undisturbed grains count.** Leading surface: the normal force acts on
   the face whose normal points along the element's velocity (the smoothed rule of
   :mod:`mjrft.laws.common`, so a thin leg's two faces add up to one). Undisturbed grains: for a leg
   rotating about its axle an element moves into space that the leg has just cleared when another
   part of the leg at the same distance from the axle is ahead of it in the direction of rotation
   (less than half a turn ahead): that part swept the very same point earlier in the stroke. Such
   elements feel nothing (:func:`shadowed_elements`, exact for any profile).

   *The sign of psi.* The paper states this rule twice with opposite signs: section 2.2 integrates
   an element "only when psi > 0", while section 4 and fig. 12 (psi measured counterclockwise from
   v to the element's tangent) say "a negative psi corresponds to the situation where the leg
   element is in contact" and that psi is negative along the whole of the straight ... semicircle
   legs. Read with section 2.2's sign, those three legs would feel no force at all, so we follow
   section 4 and fig. 12, and implement the rule as geometry, with no signed angle: for the
   semi-ellipse family with its convex side leading it is exactly fig. 12's sign change, an element
   counting iff its hip-to-tip tangent points away from the axle (t . r_hat > 0); only legs with
   b > sqrt(2) a (the bent and very bent legs) have a part curving back toward the axle (fig. 12:
   psi changes sign "as xi approaches 0", toward the tip), and that part feels nothing (22 and 42 of
   100 elements), which makes these legs lose their force long before they leave the sand.

   *Which side leads.* The paper's legs turn with the convex side leading: section 4 says the legs
   enter the sand at different moments but leave it at the same moment "thanks to the
   semi-elliptical shape", which holds only when the tip (2a from the axle for every leg) trails;
   with the concave side leading the tip would enter first for every leg and the legs would leave
   at different moments, and the shadowed part would sit at the hip end instead of toward the tip.

   *Per element, from the ground memory.* A law of the coupler sees one element's depth, unit normal,
   unit motion and speed, and these do not decide the rule: a shadowed element of the very bent leg
   and an element of the semicircle leg turning the other way about an axle mirrored through that
   element have identical inputs (tested), and only the second counts. The rule needs the rest of
   the leg: here it lives in the whole-leg functions (:func:`rotating_leg_profile`,
   :func:`hybrid_leg_forces` with an ``axle``; :func:`hybrid_leg_forces` without an axle applies only
   the leading-surface rule). Through the coupler, a terrain with a ground memory applies it per
   element from the memory's wake (:func:`mjrft.ground.in_wake`: an element moving into depth slabs
   of a cell that a leading face passed through earlier than it could have itself feels nothing;
   docs/terrain.md, "Ground memory"); without a memory a bent leg's shadowed part pushes
   (``mjrft.tools.rigs`` docstring; ``mjrft validate --case hybrid_leg_family_memory`` compares both
   with this model).

4. **Density correction** k = lambda x (maximum penetration depth Delta d), lambda = 0.0325 (forward
   force) and 0.06 (support force). The unit of lambda is not stated; we read it as per millimetre
   (32.5 /m and 60 /m), the only reading for which k is of order one (k_f = 1.3, k_s = 2.4 for the
   semicircle leg's 40 mm); per centimetre would shrink forces ten-fold, against the stated purpose
   (density, hence force, grows under the leg). Delta d is a property of the leg and the axle
   height, the deepest any point of the leg reaches over a turn (largest distance from the axle
   minus the axle's height above the sand: 4.0 cm for the straight ... semicircle legs, 4.05 cm bent,
   5.39 cm very bent), not of the angles a caller happens to sample. k_f multiplies the horizontal
   and k_s the vertical component of every element force, and the torque is taken from the
   corrected forces.

5. **Speed**: an optional user curve of (speed m/s, factor) pairs, linearly interpolated in the
   element's speed and held at its end values; default a flat factor 1. The paper scales its forces
   by a measured F_perp(v) (fig. 6, 1-100 cm/s at 3 cm depth) whose numbers are not in the text, and
   finds the leg forces "negligibly" changed by omega below 11 rad/s (fig. 9, omega = 1, 4, 7,
   10 rad/s), which a flat factor reproduces. The per-element law has no speed factor (a parameter
   vector has no room for a curve), so it is the flat default there.

6. **Defaults (assumptions; the paper measured its friction angles by shear tests without giving
   them)**: phi = 35 deg (a medium quartz river sand), phi_w = 20 deg (about 0.57 phi, the usual
   1/2-2/3 phi of a smooth rigid plate); bulk unit weight gamma_s = 1345.4 kg/m^3 x 9.81 m/s^2
   (the paper's river sand, 1.3454 g/cm^3); leg width W = 2.54 cm (not in the reference: Li 2013's
   leg-rotation rig legs, section 6); leg family a = 4.5 cm fixed, b = a/9, a/2, a, a/0.67, a/0.5,
   axle h = 5 cm above the surface.

Geometry and sign conventions (:func:`rotating_leg_profile`)
-----------------------------------------------------------
The leg frame has u along the leg (hip at the axle, tip at u = 2a) and w across it; the profile is
u = a (1 - cos t), w = b sin t, t in [0, pi] (:func:`semi_ellipse_leg`). The leg angle theta is
measured from straight down, positive when the leg has swung backward (toward -x): e_u =
(-sin theta, -cos theta), e_w = (-cos theta, sin theta) = d e_u / d theta (the direction of rotation).
A point at leg coordinates (u, w) is at axle + u e_u + bulge w e_w; ``bulge = +1`` (default) puts the
convex side leading. omega > 0 increases theta, so the buried part sweeps backward and the grains
push the leg forward (F_f > 0 is thrust). Forces are those of the grains on the leg: F_f along +x,
F_s along +z; ``torque`` is the torque about +y (the rotation axis of omega > 0) that the drive must
supply against the grains, -sum (r x F)_y with r from the axle (positive = resisting when omega > 0).
The paper's F_f = sum (F_perp cos b + F_par sin b) dl and F_s = sum (F_perp sin b - F_par cos b) dl
are these vector sums written with the element angle b.

Per-element law ``hybrid`` (law id 5) for the coupler
-----------------------------------------------------
Same stress interface as the other laws, for a thin leg element with unit normal n and unit motion m:
sin psi = |n . m|; stress = lead_weight(n . m) / W x (-F_perp n - F_par s), s the unit tangential
motion; horizontal components x k_f, vertical x k_s. Medium constants (``Medium.extra``):
``hybrid_width`` (W, 0.0254 m), ``hybrid_phi`` / ``hybrid_phi_w`` (radians; 35 / 20 deg),
``hybrid_unit_weight`` (N/m^3; default 9.81 x the medium's bulk density when known, else the river
sand's), ``hybrid_c_par_ratio`` (0.37), ``hybrid_c_perp_h`` / ``hybrid_c_par_h`` (N/m^3, C^h per unit
length = value x d x W; defaults 0 and, for C_par^h, the continuity value C_PAR_H_FRACTION x C_par of
item 2), ``hybrid_max_depth`` (m, the stroke's Delta d; default none, k = 1; the rigs set it). The
undisturbed-grain (shadow) rule (item 3) only with a ground memory (its wake); the speed curve (item 5)
not per element.
Parameter slots 22..31: 22 W, 23-25 gamma_s g0, g1, g2, 26 C_par/C_perp, 27 C_perp^h coefficient,
28 C_par^h coefficient, 29 k_f, 30 k_s, 31 C_par^h as a fraction of C_par (C_par^h = slot 31 x
C_par + slot 28 x d x W).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..errors import check_finite, check_positive
from ..media import G
from ..params import (P_HYB_E0, P_HYB_E1, P_HYB_E2, P_HYB_KF, P_HYB_KS, P_HYB_PAR_H, P_HYB_PAR_H_FRAC,
                      P_HYB_PERP_H, P_HYB_RATIO, P_HYB_W)
from .common import LEAD_EPS, TINY, lead_weight

# --- constants (the hybrid paper's secs. 2.3-2.4; assumptions in the module docstring) ----------
PHI = math.radians(35.0)  # internal friction angle (assumption)
PHI_W = math.radians(20.0)  # sand-leg friction angle (assumption)
RHO_BULK = 1345.4  # kg/m^3, the paper's river sand
GAMMA_S = RHO_BULK * G  # N/m^3
C_PAR_RATIO = 0.37  # C_par / C_perp (paper: 0.37 +- 0.02)
PSI_BREAK = math.radians(36.0)  # region I / II boundary, maximum of F_par
SIN_BREAK = math.sin(PSI_BREAK)
COS_BREAK = math.cos(PSI_BREAK)
# C_par^h / C_par from eq. (4) continuous at 36 deg with its maximum C_par there (docstring item 2)
C_PAR_H_FRACTION = (COS_BREAK - SIN_BREAK) / (COS_BREAK * (1.0 - SIN_BREAK))
LAMBDA_FORWARD = 32.5  # 1/m (0.0325 per mm)
LAMBDA_SUPPORT = 60.0  # 1/m (0.06 per mm)
LEG_WIDTH = 0.0254  # m, assumption (Li 2013 leg-rotation rig)
LEG_A = 0.045  # m, semicircle case a = b = 4.5 cm
AXLE_HEIGHT = 0.05  # m
LEG_FAMILY = {"straight": 9.0, "less_straight": 2.0, "semicircle": 1.0, "bent": 0.67, "very_bent": 0.5}  # a / b
X_TABLE = 40.0  # G(x) tabulated on x = (d - W) / W in [0, X_TABLE]
N_TABLE = 161



# ================================================================================================
# Coulomb wedge
# ================================================================================================
def _check_angles(phi, phi_w):
    phi = check_positive("phi", phi)
    phi_w = check_positive("phi_w", phi_w, allow_zero=True)
    if phi + phi_w >= math.pi / 2:
        raise ValueError(f"phi + phi_w must be < pi/2 for a passive wedge, got phi={phi!r}, phi_w={phi_w!r} (radians)")
    return phi, phi_w


def active_angle(phi=PHI) -> float:
    """Critical active wedge angle a_max = atan(tan phi + sec phi / sqrt 2) (radians)."""
    phi = check_positive("phi", phi)
    return math.atan(math.tan(phi) + 1.0 / (math.cos(phi) * math.sqrt(2.0)))


def _active(h1, gamma_s, phi):
    a1 = active_angle(phi)
    f = (1.0 / math.tan(a1)) / (math.tan(phi) + 1.0 / math.tan(a1 - phi))
    return a1, f, gamma_s * h1 ** 2 * f / (2.0 * math.cos(phi)), gamma_s * h1 ** 2 * f / (2.0 * math.sin(a1 - phi))


def passive_force(a2, h1, h0, gamma_s=GAMMA_S, phi=PHI, phi_w=PHI_W):
    """P_w(a2) of the passive region for a trial angle ``a2`` (radians; numpy broadcasts)."""
    a2 = np.asarray(a2, dtype=float)
    h1 = np.asarray(h1, dtype=float)
    h0 = np.asarray(h0, dtype=float)
    a1, _, _, x1 = _active(h1, gamma_s, phi)
    w2 = 0.5 * gamma_s * ((h0 + h1) ** 2 / np.tan(a2) - h1 ** 2 / math.tan(a1))
    return (w2 * np.sin(a2 + phi) + x1 * np.sin(a2 - a1 + 2.0 * phi)) / np.cos(phi_w + a2 + phi)


def wedge_force(h1, h0, gamma_s=GAMMA_S, phi=PHI, phi_w=PHI_W, *, n_grid=512, n_golden=60) -> dict:
    """Coulomb wedge force per unit bar length (module docstring, item 1); numpy, broadcasts h1 and h0.

    ``h1`` top-edge depth (m, >= 0), ``h0`` bar width (m, >= 0), ``gamma_s`` bulk unit weight (N/m^3),
    ``phi``/``phi_w`` in radians. Returns a dict of arrays: ``F_w`` (= C_perp, N/m, horizontal),
    ``P_w``, ``a1`` (= a_max), ``a2`` (= a_min), ``P``, ``X1``, ``W1``, ``W2``.
    """
    phi, phi_w = _check_angles(phi, phi_w)
    gamma_s = check_positive("gamma_s", gamma_s)
    h1 = np.asarray(h1, dtype=float)
    h0 = np.asarray(h0, dtype=float)
    if not (np.all(np.isfinite(h1)) and np.all(np.isfinite(h0))):
        raise ValueError("wedge_force: h1 and h0 must be finite")
    if np.any(h1 < 0) or np.any(h0 < 0):
        raise ValueError(f"wedge_force: h1 and h0 must be >= 0, got min h1 {float(h1.min())!r}, min h0 {float(h0.min())!r}")
    h1, h0 = np.broadcast_arrays(h1, h0)
    shape = h1.shape
    b1, b0 = h1.ravel(), h0.ravel()
    ub = math.pi / 2 - phi - phi_w
    grid = np.linspace(0.0, ub, n_grid + 2)[1:-1]
    pw = passive_force(grid[None, :], b1[:, None], b0[:, None], gamma_s, phi, phi_w)
    i = np.argmin(pw, axis=1)
    lo = np.where(i > 0, grid[np.maximum(i - 1, 0)], 0.5 * grid[0])
    hi = np.where(i < n_grid - 1, grid[np.minimum(i + 1, n_grid - 1)], 0.5 * (grid[-1] + ub))
    r = (math.sqrt(5.0) - 1.0) / 2.0
    c = hi - r * (hi - lo)
    d = lo + r * (hi - lo)
    fc = passive_force(c, b1, b0, gamma_s, phi, phi_w)
    fd = passive_force(d, b1, b0, gamma_s, phi, phi_w)
    for _ in range(n_golden):
        left = fc < fd
        lo, hi = np.where(left, lo, c), np.where(left, d, hi)
        c_new = np.where(left, hi - r * (hi - lo), d)
        d_new = np.where(left, c, lo + r * (hi - lo))
        fc, fd = (np.where(left, passive_force(c_new, b1, b0, gamma_s, phi, phi_w), fd),
                  np.where(left, fc, passive_force(d_new, b1, b0, gamma_s, phi, phi_w)))
        c, d = c_new, d_new
    a2 = 0.5 * (lo + hi)
    p_w = passive_force(a2, b1, b0, gamma_s, phi, phi_w)
    a1, _, p, x1 = _active(b1, gamma_s, phi)
    w1 = 0.5 * gamma_s * b1 ** 2 / math.tan(a1)
    w2 = 0.5 * gamma_s * ((b0 + b1) ** 2 / np.tan(a2) - b1 ** 2 / math.tan(a1))
    zero = (b0 == 0) & (b1 == 0)
    p_w = np.where(zero, 0.0, p_w)
    out = {"F_w": p_w * math.cos(phi_w), "P_w": p_w, "a2": a2, "P": p, "X1": x1, "W1": w1,
           "W2": np.where(zero, 0.0, w2)}
    out = {k: np.reshape(v, shape) for k, v in out.items()}
    out["a1"] = a1
    return out


@functools.lru_cache(maxsize=64)
def wedge_shape(phi=PHI, phi_w=PHI_W):
    """Dimensionless C_perp shape for the bottom-strip convention (module docstring, item 1).

    Returns ``(x, G, (g0, g1, g2), max_rel_err)``: G(x) = C_perp / (gamma_s W^2) at x = (d - W)/W on
    [0, X_TABLE], the quadratic fit (g0 = G(0) exact) and its largest relative error on the table.
    """
    x = np.linspace(0.0, X_TABLE, N_TABLE)
    g = wedge_force(x, 1.0, 1.0, phi, phi_w)["F_w"]
    g0 = float(g[0])
    a = np.stack([x, x * x], axis=1)
    (g1, g2), *_ = np.linalg.lstsq(a, g - g0, rcond=None)
    fit = g0 + g1 * x + g2 * x * x
    x.setflags(write=False)
    g.setflags(write=False)
    return x, g, (g0, float(g1), float(g2)), float(np.max(np.abs(fit - g) / g))


def c_perp(depth, width=LEG_WIDTH, gamma_s=GAMMA_S, phi=PHI, phi_w=PHI_W):
    """C_perp(d) per unit leg length (N/m) of an element at depth ``d`` (m) of a leg of width ``width``.

    Bottom-strip convention (module docstring, item 1): 0 at and above the surface, gamma_s g0 d^2 up
    to d = W, then gamma_s W^2 G((d - W)/W) from the tabulated exact wedge (quadratic fit beyond).
    """
    width = check_positive("width", width)
    gamma_s = check_positive("gamma_s", gamma_s)
    x_t, g_t, (g0, g1, g2), _ = wedge_shape(*_check_angles(phi, phi_w))
    d = np.asarray(depth, dtype=float)
    x = np.maximum(d - width, 0.0) / width
    # quadratic fit + the interpolated (tiny, smooth) residual of the exact table; held beyond X_TABLE
    gx = g0 + g1 * x + g2 * x * x + np.interp(x, x_t, g_t - (g0 + g1 * x_t + g2 * x_t * x_t))
    shallow = gamma_s * g0 * np.clip(d, 0.0, None) ** 2
    return np.where(d <= width, shallow, gamma_s * width * width * gx)


# ================================================================================================
# Bar-drag fit and the leg model
# ================================================================================================
def _speed_curve(curve):
    if curve is None:
        return None
    try:
        arr = np.asarray(curve, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"speed_curve must be an array of (speed, factor) pairs, got {curve!r}") from None
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 1:
        raise ValueError(f"speed_curve must have shape (n, 2) of (speed m/s, factor) pairs, got shape {arr.shape}")
    for k, (v, f) in enumerate(arr):
        if not (math.isfinite(v) and math.isfinite(f)):
            raise ValueError(f"speed_curve row {k}: (speed, factor) must be finite, got ({float(v)!r}, {float(f)!r})")
        if v < 0 or f < 0:
            raise ValueError(f"speed_curve row {k}: speed and factor must be >= 0, got ({float(v)!r}, {float(f)!r})")
    if np.any(np.diff(arr[:, 0]) <= 0):
        k = int(np.argmax(np.diff(arr[:, 0]) <= 0)) + 1
        raise ValueError(f"speed_curve row {k}: speeds must be strictly increasing, got {float(arr[k, 0])!r} after {float(arr[k - 1, 0])!r}")
    arr.setflags(write=False)
    return arr


def _table(name, table):
    if table is None:
        return None
    try:
        d, v = (np.asarray(c, dtype=float).ravel() for c in table)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (depths, values) of numbers") from None
    if d.size != v.size or d.size < 1:
        raise ValueError(f"{name}: depths and values must have the same non-zero length, got {d.size} and {v.size}")
    if not (np.all(np.isfinite(d)) and np.all(np.isfinite(v))):
        raise ValueError(f"{name}: depths and values must be finite")
    if np.any(np.diff(d) <= 0) or d[0] < 0:
        raise ValueError(f"{name}: depths must be >= 0 and strictly increasing")
    if d[0] > 0:  # zero at the surface, linear up to the first measured depth
        d, v = np.concatenate([[0.0], d]), np.concatenate([[0.0], v])
    return d, v


@dataclass(frozen=True)
class HybridModel:
    """The hybrid model's constants (module docstring); every field has a documented default.

    ``c_perp_h_coef`` / ``c_par_h_coef``: C^h per unit length = coef x d x W (N/m^3); None for
    ``c_par_h_coef`` means C_par^h = :data:`C_PAR_H_FRACTION` x C_par (module docstring, item 2). ``speed_curve``: (n, 2) (speed m/s, factor).
    ``c_perp_table`` / ``c_perp_h_table`` / ``c_par_h_table``: optional measured (depths, N/m) that
    replace the wedge / the C^h defaults (linear interpolation from zero at the surface; the deepest
    value is held below the deepest measurement).
    """

    width: float = LEG_WIDTH
    phi: float = PHI
    phi_w: float = PHI_W
    gamma_s: float = GAMMA_S
    c_par_ratio: float = C_PAR_RATIO
    c_perp_h_coef: float = 0.0
    c_par_h_coef: float | None = None
    lambda_forward: float = LAMBDA_FORWARD
    lambda_support: float = LAMBDA_SUPPORT
    speed_curve: object = None
    c_perp_table: object = None
    c_perp_h_table: object = None
    c_par_h_table: object = None

    def __post_init__(self):
        s = object.__setattr__
        s(self, "width", check_positive("width", self.width))
        phi, phi_w = _check_angles(self.phi, self.phi_w)
        s(self, "phi", phi)
        s(self, "phi_w", phi_w)
        s(self, "gamma_s", check_positive("gamma_s", self.gamma_s))
        s(self, "c_par_ratio", check_positive("c_par_ratio", self.c_par_ratio))
        s(self, "c_perp_h_coef", check_finite("c_perp_h_coef", self.c_perp_h_coef))
        if self.c_par_h_coef is not None:
            s(self, "c_par_h_coef", check_finite("c_par_h_coef", self.c_par_h_coef))
        s(self, "lambda_forward", check_positive("lambda_forward", self.lambda_forward, allow_zero=True))
        s(self, "lambda_support", check_positive("lambda_support", self.lambda_support, allow_zero=True))
        s(self, "speed_curve", _speed_curve(self.speed_curve))
        for name in ("c_perp_table", "c_perp_h_table", "c_par_h_table"):
            s(self, name, _table(name, getattr(self, name)))

    @classmethod
    def from_fit(cls, fit, **kw) -> "HybridModel":
        """A model using measured bar-drag constants (:func:`mjrft.tools.calibration.fit_hybrid_constants`)."""
        return cls(c_par_ratio=fit.c_par_ratio, c_perp_table=(fit.depth, fit.c_perp),
                   c_perp_h_table=(fit.depth, fit.c_perp_h), c_par_h_table=(fit.depth, fit.c_par_h), **kw)

    # --- constants against depth (N per metre of leg) ------------------------------------------
    def c_perp(self, depth):
        if self.c_perp_table is not None:
            return np.interp(depth, *self.c_perp_table) * (np.asarray(depth) > 0)
        return c_perp(depth, self.width, self.gamma_s, self.phi, self.phi_w)

    def c_par(self, depth):
        return self.c_par_ratio * self.c_perp(depth)

    def c_perp_h(self, depth):
        d = np.clip(np.asarray(depth, dtype=float), 0.0, None)
        if self.c_perp_h_table is not None:
            return np.interp(d, *self.c_perp_h_table) * (d > 0)
        return self.c_perp_h_coef * d * self.width

    def c_par_h(self, depth):
        d = np.clip(np.asarray(depth, dtype=float), 0.0, None)
        if self.c_par_h_table is not None:
            return np.interp(d, *self.c_par_h_table) * (d > 0)
        if self.c_par_h_coef is None:
            return C_PAR_H_FRACTION * self.c_par(d)
        return self.c_par_h_coef * d * self.width

    # --- bar-drag fit ----------------------------------------------------------------------------
    def f_perp(self, psi, depth):
        """F_perp (N/m) at angle ``psi`` (radians, 0..pi/2) and depth (m)."""
        sp = np.abs(np.sin(psi))
        ch = self.c_perp_h(depth)
        return ch + (self.c_perp(depth) - ch) * sp

    def f_par(self, psi, depth):
        """F_par (N/m): region I below 36 deg, region II above, meeting at C_par (module docstring)."""
        sp = np.abs(np.sin(psi))
        cp = np.abs(np.cos(psi))
        cpar = self.c_par(depth)
        ch = self.c_par_h(depth)
        return np.where(sp <= SIN_BREAK, ch + (cpar - ch) * sp / SIN_BREAK, cpar * cp / COS_BREAK)

    def speed_factor(self, speed):
        speed = np.asarray(speed, dtype=float)
        if self.speed_curve is None:
            return np.ones_like(speed)
        return np.interp(speed, self.speed_curve[:, 0], self.speed_curve[:, 1])

    def density_factors(self, max_depth):
        """(k_f, k_s) = lambda x maximum penetration depth (m)."""
        d = check_positive("max_depth", max_depth, allow_zero=True)
        return self.lambda_forward * d, self.lambda_support * d


def _lead(c):
    return np.clip(0.5 + c / (2.0 * LEAD_EPS), 0.0, 1.0)


def _as2(name, a, n=None):
    arr = np.asarray(a, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{name} must have shape (n, 2) (x, z in the rig plane), got {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise ValueError(f"{name} has {arr.shape[0]} rows, expected {n}")
    if not np.all(np.isfinite(arr)):
        i = int(np.argwhere(~np.isfinite(arr))[0, 0])
        raise ValueError(f"{name} row {i} is not finite: {arr[i].tolist()!r}")
    return arr


def shadowed_elements(points, axle, omega_sign=1.0):
    """Elements (bool, (n,)) that move into space the leg has just cleared (module docstring, item 3).

    ``points`` (n, 2) element centres in order along the leg (world or leg frame, rigidly rotating
    about ``axle``), ``omega_sign`` > 0 for rotation about +y (x toward -z). Element i is shadowed
    when the profile (the polyline through the centres) crosses the circle of radius |p_i - axle| at a
    point ahead of p_i in the direction of rotation by an angle in (0, pi).
    """
    p = _as2("points", points) - np.asarray(axle, dtype=float).reshape(1, 2)
    n = p.shape[0]
    rho = np.hypot(p[:, 0], p[:, 1])
    # rotation about +y moves (x, z) toward (z, -x): the angle atan2(-z, x) increases with it
    ang = np.arctan2(-p[:, 1], p[:, 0])
    if n < 2:
        return np.zeros(n, dtype=bool)
    r0, r1 = rho[:-1], rho[1:]
    ri = rho[:, None]
    dr = (r1 - r0)[None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (ri - r0[None, :]) / dr
    cross = (dr != 0) & (t >= 0) & (t <= 1)
    cx = p[:-1, 0][None, :] + t * (p[1:, 0] - p[:-1, 0])[None, :]
    cz = p[:-1, 1][None, :] + t * (p[1:, 1] - p[:-1, 1])[None, :]
    ca = np.arctan2(-cz, cx)
    delta = np.mod(ca - ang[:, None] + np.pi, 2 * np.pi) - np.pi
    delta = delta * (1.0 if omega_sign >= 0 else -1.0)
    ahead = cross & (delta > 1e-9) & (delta < np.pi)
    return np.any(ahead, axis=1)


def _leg_forces(pts, tan, vel, dl, model, counted, k_f, k_s, surface, axle):
    depth = surface - pts[:, 1]
    speed = np.hypot(vel[:, 0], vel[:, 1])
    tl = np.hypot(tan[:, 0], tan[:, 1])
    t = tan / tl[:, None]
    nrm = np.stack([-t[:, 1], t[:, 0]], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        vh = np.where(speed[:, None] > 0, vel / np.where(speed > 0, speed, 1.0)[:, None], 0.0)
    cn = np.sum(nrm * vh, axis=1)
    ct = np.sum(t * vh, axis=1)
    psi = np.arctan2(np.abs(cn), np.abs(ct))
    active = (depth > 0) & (speed > 0) & counted
    dpos = np.where(active, depth, 0.0)
    fperp = model.f_perp(psi, dpos)
    fpar = model.f_par(psi, dpos)
    net = _lead(cn) - _lead(-cn)  # both faces of the thin leg, smoothed leading-surface rule
    sf = model.speed_factor(speed)
    per_len = -(fperp * net)[:, None] * nrm - (fpar * np.sign(ct))[:, None] * t
    f = np.where(active[:, None], per_len * (sf * dl)[:, None], 0.0)
    f[:, 0] *= k_f
    f[:, 1] *= k_s
    r = pts - axle.reshape(1, 2)
    tau_y = np.sum(r[:, 1] * f[:, 0] - r[:, 0] * f[:, 1])
    return {"F_f": float(np.sum(f[:, 0])), "F_s": float(np.sum(f[:, 1])), "torque": float(-tau_y),
            "forces": f, "psi": psi, "depth": depth, "counted": active}


def hybrid_leg_forces(points, tangents, velocities, dl, *, model: HybridModel | None = None, axle=None,
                      max_depth=None, undisturbed=None, surface=0.0, density_correction=True) -> dict:
    """Forward force F_f, support force F_s and torque of one leg configuration (module docstring).

    ``points``, ``tangents``, ``velocities``: (n, 2) arrays (x forward, z up; m, -, m/s) of the element
    centres, tangents (any length, any orientation) and velocities in the rig plane; ``dl`` element
    lengths (m, scalar or (n,)); ``surface`` the sand height (m). ``axle`` (2,): if given, the torque is
    about it and, unless ``undisturbed`` (bool (n,)) is passed, the shadow rule assumes a rigid
    rotation about it (direction from the velocities). ``max_depth``: maximum penetration depth of the
    stroke for the density correction (default: the deepest element now); ``density_correction=False``
    uses k = 1. Returns ``F_f``, ``F_s`` (N), ``torque`` (N m, drive torque about +y), per-element
    ``forces`` (n, 2), ``psi``, ``depth``, ``counted``, ``k_forward``, ``k_support``.
    """
    model = model or HybridModel()
    pts = _as2("points", points)
    n = pts.shape[0]
    tan = _as2("tangents", tangents, n)
    vel = _as2("velocities", velocities, n)
    if np.any(np.hypot(tan[:, 0], tan[:, 1]) == 0):
        raise ValueError(f"tangents row {int(np.argmin(np.hypot(tan[:, 0], tan[:, 1])))} is zero")
    dl = np.broadcast_to(np.asarray(dl, dtype=float), (n,))
    if not np.all(np.isfinite(dl)) or np.any(dl < 0):
        raise ValueError(f"dl must be finite and >= 0, got min {float(dl.min())!r}")
    surface = check_finite("surface", surface)
    ax = np.zeros(2) if axle is None else np.asarray(axle, dtype=float).reshape(2)
    if undisturbed is not None:
        counted = np.broadcast_to(np.asarray(undisturbed, dtype=bool), (n,))
    elif axle is not None:
        r = pts - ax
        w = np.sum(r[:, 1] * vel[:, 0] - r[:, 0] * vel[:, 1])
        counted = ~shadowed_elements(pts, ax, 1.0 if w >= 0 else -1.0)
    else:
        counted = np.ones(n, dtype=bool)
    if density_correction:
        dmax = max_depth if max_depth is not None else max(0.0, float(np.max(surface - pts[:, 1])))
        k_f, k_s = model.density_factors(dmax)
    else:
        k_f = k_s = 1.0
    out = _leg_forces(pts, tan, vel, dl, model, counted, k_f, k_s, surface, ax)
    out["k_forward"], out["k_support"] = k_f, k_s
    return out


# ================================================================================================
# Leg profiles
# ================================================================================================
def semi_ellipse_leg(a, b, n=100) -> dict:
    """A semi-elliptic leg cut into ``n`` elements of equal arc length (module docstring, geometry).

    ``a`` half the hip-to-tip length (m), ``b`` the bulge (m). Returns ``points`` (n, 2) element centres
    and ``tangents`` (n, 2) unit hip-to-tip tangents in the leg frame (u along the leg, w across),
    ``dl`` (n,) element lengths, ``length``, ``a``, ``b``.
    """
    a = check_positive("a", a)
    b = check_positive("b", b)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise ValueError(f"n must be an integer >= 2, got {n!r}")
    t = np.linspace(0.0, math.pi, 200 * n + 1)
    u = a * (1.0 - np.cos(t))
    w = b * np.sin(t)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(u), np.diff(w)))])
    # refine the arc length with Simpson on the speed |(a sin t, b cos t)|
    spd = np.hypot(a * np.sin(t), b * np.cos(t))
    h = t[1] - t[0]
    seg = h / 6.0 * (spd[:-1] + 4.0 * np.hypot(a * np.sin(t[:-1] + h / 2), b * np.cos(t[:-1] + h / 2)) + spd[1:])
    s = np.concatenate([[0.0], np.cumsum(seg)])
    length = float(s[-1])
    edges = np.linspace(0.0, length, n + 1)
    tm = np.interp(0.5 * (edges[:-1] + edges[1:]), s, t)
    pts = np.stack([a * (1.0 - np.cos(tm)), b * np.sin(tm)], axis=1)
    tan = np.stack([a * np.sin(tm), b * np.cos(tm)], axis=1)
    tan /= np.hypot(tan[:, 0], tan[:, 1])[:, None]
    return {"points": pts, "tangents": tan, "dl": np.diff(edges), "length": length, "a": a, "b": b}


def leg_pose(leg, theta, h=AXLE_HEIGHT, bulge=1):
    """World (x, z) centres and tangents of ``leg`` at leg angle ``theta`` about an axle at (0, h)."""
    eu = np.array([-math.sin(theta), -math.cos(theta)])
    ew = np.array([-math.cos(theta), math.sin(theta)]) * bulge
    p = leg["points"]
    t = leg["tangents"]
    pts = np.array([0.0, h]) + p[:, :1] * eu + p[:, 1:] * ew
    tan = t[:, :1] * eu + t[:, 1:] * ew
    return pts, tan


def stroke_depth(leg, h, surface=0.0) -> float:
    """Delta d (m): the deepest any point of ``leg`` reaches over a turn about an axle ``h`` above the
    ground at height ``surface`` (module docstring, item 4): its largest distance from the axle minus
    the axle's height above the sand, >= 0. Exact for a :func:`semi_ellipse_leg` (its curve, not its
    element centres); other legs given as ``points`` (leg frame, hip at the origin) use their points.
    """
    h = check_finite("h", h)
    surface = check_finite("surface", surface)
    if "a" in leg and "b" in leg:
        t = np.linspace(0.0, math.pi, 20001)
        reach = float(np.max(np.hypot(leg["a"] * (1.0 - np.cos(t)), leg["b"] * np.sin(t))))
    else:
        pts = _as2("leg points", leg["points"])
        reach = float(np.max(np.hypot(pts[:, 0], pts[:, 1])))
    return max(0.0, reach - (h - surface))


def rotating_leg_profile(leg, h, omega, angles, *, model: HybridModel | None = None, bulge=1, surface=0.0,
                         max_depth=None, density_correction=True) -> dict:
    """F_f, F_s and torque against leg angle for ``leg`` rotating at constant ``omega`` (rad/s).

    ``leg`` from :func:`semi_ellipse_leg`; axle at height ``h`` (m) above the sand surface; ``angles``
    leg angles (radians from straight down, positive backward); ``bulge`` +1 convex side leading, -1
    trailing. ``max_depth`` (Delta d of the density correction) defaults to :func:`stroke_depth`, the
    deepest the leg reaches over a turn, whatever ``angles`` cover.
    Returns arrays ``angle``, ``F_f``, ``F_s``, ``torque``, ``depth`` (deepest element per angle) and
    ``n_counted``, plus ``shadowed`` (the elements the undisturbed-grain rule drops), ``k_forward``,
    ``k_support``, ``max_depth``.
    """
    model = model or HybridModel()
    h = check_finite("h", h)
    omega = check_finite("omega", omega)
    if bulge not in (1, -1):
        raise ValueError(f"bulge must be +1 or -1, got {bulge!r}")
    ang = np.atleast_1d(np.asarray(angles, dtype=float))
    if ang.ndim != 1 or not np.all(np.isfinite(ang)):
        bad = ang.ravel()[~np.isfinite(ang.ravel())]
        raise ValueError(f"angles must be a finite 1-D array, got bad value {bad[0] if bad.size else ang.shape!r}")
    axle = np.array([0.0, h])
    dl = np.asarray(leg["dl"], dtype=float)
    pts0, _ = leg_pose(leg, 0.0, h, bulge)
    shadow = shadowed_elements(pts0, axle, 1.0 if omega >= 0 else -1.0)
    depth = np.empty(ang.size)
    poses = []
    for i, th in enumerate(ang):
        pts, tan = leg_pose(leg, th, h, bulge)
        poses.append((pts, tan))
        depth[i] = max(0.0, float(np.max(surface - pts[:, 1])))
    dmax = stroke_depth(leg, h, surface) if max_depth is None else check_positive("max_depth", max_depth,
                                                                                  allow_zero=True)
    k_f, k_s = model.density_factors(dmax) if density_correction else (1.0, 1.0)
    out = {k: np.empty(ang.size) for k in ("F_f", "F_s", "torque")}
    n_counted = np.empty(ang.size, dtype=int)
    for i, (pts, tan) in enumerate(poses):
        r = pts - axle
        vel = omega * np.stack([r[:, 1], -r[:, 0]], axis=1)
        res = _leg_forces(pts, tan, vel, dl, model, ~shadow, k_f, k_s, surface, axle)
        for k in out:
            out[k][i] = res[k]
        n_counted[i] = int(np.count_nonzero(res["counted"]))
    out.update(angle=ang, depth=depth, n_counted=n_counted, shadowed=shadow, k_forward=k_f, k_support=k_s,
               max_depth=dmax)
    return out


def leg_family(a=LEG_A, n=100) -> dict:
    """The five test legs (a fixed, b = a / ratio for ratios 9, 2, 1, 0.67, 0.5), by name."""
    return {name: semi_ellipse_leg(a, a / ratio, n) for name, ratio in LEG_FAMILY.items()}


def leg_family_profiles(angles, omega=1.0, h=AXLE_HEIGHT, a=LEG_A, n=100, **kw) -> dict:
    """:func:`rotating_leg_profile` for every leg of :func:`leg_family` (omega default 1 rad/s, the low
    end of the paper's 1-10 rad/s; with the default flat speed factor the result does not depend on it)."""
    return {name: rotating_leg_profile(leg, h, omega, angles, **kw) for name, leg in leg_family(a, n).items()}


# ================================================================================================
# Per-element law (id 5)
# ================================================================================================
@njit(cache=True)
def hybrid_stress(depth, nx, ny, nz, mx, my, mz, speed, p):
    """Stress (Pa) on one thin-leg element (module docstring, per-element law)."""
    if depth <= 0.0:
        return 0.0, 0.0, 0.0
    c = nx * mx + ny * my + nz * mz
    lw = lead_weight(c)
    if lw == 0.0:
        return 0.0, 0.0, 0.0
    w = p[P_HYB_W]
    sp = min(1.0, abs(c))
    cp = math.sqrt(max(0.0, 1.0 - sp * sp))
    if depth <= w:
        cperp = p[P_HYB_E0] * depth * depth
    else:
        x = depth - w
        cperp = p[P_HYB_E0] * w * w + p[P_HYB_E1] * w * x + p[P_HYB_E2] * x * x
    cperp_h = p[P_HYB_PERP_H] * depth * w
    cpar = p[P_HYB_RATIO] * cperp
    cpar_h = p[P_HYB_PAR_H_FRAC] * cpar + p[P_HYB_PAR_H] * depth * w
    fperp = cperp_h + (cperp - cperp_h) * sp
    if sp <= SIN_BREAK:
        fpar = cpar_h + (cpar - cpar_h) * sp / SIN_BREAK
    else:
        fpar = cpar * cp / COS_BREAK
    tx, ty, tz = mx - c * nx, my - c * ny, mz - c * nz
    tl = math.sqrt(tx * tx + ty * ty + tz * tz)
    if tl > TINY:
        tx, ty, tz = tx / tl, ty / tl, tz / tl
    else:
        tx, ty, tz = 0.0, 0.0, 0.0
    k = lw / w
    kf = p[P_HYB_KF]
    ks = p[P_HYB_KS]
    sx = -k * (fperp * nx + fpar * tx) * kf
    sy = -k * (fperp * ny + fpar * ty) * kf
    sz = -k * (fperp * nz + fpar * tz) * ks
    return sx, sy, sz


def hybrid_constants(medium) -> dict:
    """The per-element hybrid constants of ``medium`` (``extra`` values or documented defaults), checked."""
    g = medium.get
    name = getattr(medium, "name", "?")
    rho = getattr(medium, "rho_bulk", None)
    c = {
        "hybrid_width": check_positive(f"medium {name!r} hybrid_width", g("hybrid_width", LEG_WIDTH)),
        "hybrid_phi": check_positive(f"medium {name!r} hybrid_phi", g("hybrid_phi", PHI)),
        "hybrid_phi_w": check_positive(f"medium {name!r} hybrid_phi_w", g("hybrid_phi_w", PHI_W), allow_zero=True),
        "hybrid_unit_weight": check_positive(f"medium {name!r} hybrid_unit_weight",
                                             g("hybrid_unit_weight", G * rho if rho else GAMMA_S)),
        "hybrid_c_par_ratio": check_positive(f"medium {name!r} hybrid_c_par_ratio",
                                             g("hybrid_c_par_ratio", C_PAR_RATIO)),
        "hybrid_c_perp_h": check_finite(f"medium {name!r} hybrid_c_perp_h", g("hybrid_c_perp_h", 0.0)),
    }
    if c["hybrid_phi"] + c["hybrid_phi_w"] >= math.pi / 2:
        raise ValueError(f"medium {name!r}: hybrid_phi + hybrid_phi_w must be < pi/2 (radians), got "
                         f"{c['hybrid_phi']!r} + {c['hybrid_phi_w']!r}")
    par_h = g("hybrid_c_par_h", None)  # None: the continuity value C_PAR_H_FRACTION x C_par
    c["hybrid_c_par_h"] = None if par_h is None else check_finite(f"medium {name!r} hybrid_c_par_h", par_h)
    md = g("hybrid_max_depth", None)
    c["hybrid_max_depth"] = None if md is None else check_positive(f"medium {name!r} hybrid_max_depth", md,
                                                                   allow_zero=True)
    return c


def hybrid_params(medium, p):
    """The hybrid law's constants of ``medium`` into its parameter vector ``p``."""
    c = hybrid_constants(medium)
    _, _, (g0, g1, g2), _ = wedge_shape(c["hybrid_phi"], c["hybrid_phi_w"])
    gam = c["hybrid_unit_weight"]
    p[P_HYB_W] = c["hybrid_width"]
    p[P_HYB_E0] = gam * g0
    p[P_HYB_E1] = gam * g1
    p[P_HYB_E2] = gam * g2
    p[P_HYB_RATIO] = c["hybrid_c_par_ratio"]
    p[P_HYB_PERP_H] = c["hybrid_c_perp_h"]
    par_h = c["hybrid_c_par_h"]
    p[P_HYB_PAR_H] = 0.0 if par_h is None else par_h
    p[P_HYB_PAR_H_FRAC] = C_PAR_H_FRACTION if par_h is None else 0.0
    md = c["hybrid_max_depth"]
    p[P_HYB_KF] = 1.0 if md is None else LAMBDA_FORWARD * md
    p[P_HYB_KS] = 1.0 if md is None else LAMBDA_SUPPORT * md

