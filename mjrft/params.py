"""The layout of the parameter vector: one float64 row per region that the compiled kernels and the JAX path read.

Each region of a terrain (:class:`mjrft.TerrainModel`'s ``regions.params``) has one such row, built from its
medium by :func:`mjrft.laws.registry.parameter_vector` (the medium's own constants, then each law's) and completed
by the region's water layer and, when the scene turns it on, the inertial regime. Every slot is named here and
nowhere else:

======  =====================  =====================================================================
slots   name                   content (SI)
======  =====================  =====================================================================
0-8     ``P_COEFF``            Li 2013's nine Fourier coefficients A00 ... D10 (N/m^3)
9       ``P_XI``               3D-RFT's stress scale xi_n (N/m^3)
10      ``P_MU_S``             surface (leg) friction coefficient
11      ``P_ZETA``             the generic profile's scaling factor zeta (N/m^3)
12-14   ``P_AZ_DOWN`` ...      the depth-only law's alpha_z(0, pi/2), |alpha_z(0, -pi/2)|, alpha_x(pi/2, 0)
15-18   ``P_WET_*``            SGRFT saturated sand: eps_v / dv (s/m), v_base, v_cap (m/s), factor(v_cap)
19-21   ``P_WATER_*``          the water layer: depth (m), C x rho_w (kg/m^3), skin (m)
22-31   ``P_HYB_*``            the hybrid curved-leg law's per-element constants
32-34   ``P_INERTIA*``         the dry inertial regime: C x rho_bulk (kg/m^3; 0 = off), v_c^2, skin (m)
======  =====================  =====================================================================

``P_SIZE`` slots in all; the unused ones are 0. A new law takes its slots from the free ones here, and its entry
in :data:`mjrft.laws.registry.LAWS` names the function that fills them.
"""

from __future__ import annotations

# --- the medium's own constants (mjrft.media.Medium) ----------------------------------------------
P_COEFF = 0  # 9 Li coefficients, N/m^3
P_XI = 9  # 3D-RFT xi_n, N/m^3
P_MU_S = 10  # surface (leg) friction coefficient
P_ZETA = 11  # scaling factor, N/m^3
P_AZ_DOWN = 12  # alpha_z(0, pi/2), N/m^3
P_AZ_UP = 13  # |alpha_z(0, -pi/2)|, N/m^3
P_AX_DRAG = 14  # alpha_x(pi/2, 0), N/m^3
P_FIRST_FREE = 15  # the laws' own constants start here

# --- SGRFT saturated sand and the water layer (mjrft.laws.wet) -------------------------------------
P_WET_K = P_FIRST_FREE  # eps_v / dv, s/m
P_WET_VBASE = P_FIRST_FREE + 1
P_WET_VCAP = P_FIRST_FREE + 2
P_WET_FCAP = P_FIRST_FREE + 3  # factor(v_cap)
P_WATER_DEPTH = P_FIRST_FREE + 4
P_WATER_DRAG = P_FIRST_FREE + 5  # C x rho_w
P_WATER_SKIN = P_FIRST_FREE + 6

# --- the hybrid curved-leg law, per element (mjrft.laws.hybrid) ------------------------------------
P_HYB_W = P_FIRST_FREE + 7
P_HYB_E0 = P_FIRST_FREE + 8
P_HYB_E1 = P_FIRST_FREE + 9
P_HYB_E2 = P_FIRST_FREE + 10
P_HYB_RATIO = P_FIRST_FREE + 11
P_HYB_PERP_H = P_FIRST_FREE + 12
P_HYB_PAR_H = P_FIRST_FREE + 13
P_HYB_KF = P_FIRST_FREE + 14
P_HYB_KS = P_FIRST_FREE + 15
P_HYB_PAR_H_FRAC = P_FIRST_FREE + 16

# --- the dry inertial regime (mjrft.laws.inertial), filled only when a scene turns it on -----------
P_INERTIA = 32  # C x rho_bulk (kg/m^3) of the inertial pressure; 0 = off
P_INERTIA_VC2 = 33  # v_c^2 (m^2/s^2), the critical intrusion speed squared
P_INERTIA_SKIN = 34  # m, depth over which the inertial pressure ramps in below the surface

P_SIZE = 40

if not P_HYB_PAR_H_FRAC < P_INERTIA < P_INERTIA_SKIN < P_SIZE:
    raise RuntimeError("mjrft.params: overlapping parameter slots")
