"""The force laws in JAX: pure, branch-free functions of element arrays, the twins of :mod:`mjrft.laws`.

Every function here has the signature ``stress(depth, n, m, p, speed=None) -> (k, 3)``: ``depth`` (k,) in m,
positive below the surface, ``n`` (k, 3) unit outward normals, ``m`` (k, 3) unit (regularised) motion directions,
``p`` a parameter vector (P_SIZE,) shared by every element or one row per element (k, P_SIZE)
(:func:`mjrft.laws.registry.parameter_vector`, layout :mod:`mjrft.params`), ``speed`` (k,) each element's real speed in m/s (read by the rate-dependent laws
``wet`` and ``water``, which refuse to run without it; the others ignore it). The result is the stress (Pa) on
each element; the caller multiplies by area and mobilisation. They follow their numba twins line for line (the
same smoothing constants, the same choices, documented there), with ``jnp.where`` in place of each branch, so
they run under ``jit`` and ``vmap`` on any JAX device and in float32 or float64 (whatever arrays they are given).
Two take an angle's sine or cosine from the vectors where the numba law goes through ``acos`` or ``sqrt(1 - x^2)``
(equal in exact arithmetic; :func:`rft3d_generic`, :func:`hybrid`): near a cosine of 1 those turn an ulp into the
square root of an ulp, which float32 cannot afford.

Ported: ``rft`` (:func:`mjrft.laws.rft.rft_stress_batch`), ``rft3d`` (:func:`mjrft.laws.rft3d.rft3d_stress`),
``depth_only`` (:func:`mjrft.laws.depth_only.depth_only_stress`), ``wet`` (:func:`mjrft.laws.wet.wet_stress`,
SGRFT with its speed factor), ``water`` (:func:`mjrft.laws.wet.water_stress`, the water layer's drag with its
skins) and ``hybrid`` (:func:`mjrft.laws.hybrid.hybrid_stress`, the curved-leg law per element). Which function
is a law's twin, and why a law has none, the table of laws says (:data:`mjrft.laws.registry.LAWS`, each entry's
``jax`` and ``no_jax``): :data:`LAWS` and :data:`UNSUPPORTED` are built from it. The rest of an element's force
(the inertial regime, buoyancy, regions and their blending) is in :mod:`mjrft.mjx.forces`.
"""

from __future__ import annotations

import jax.numpy as jnp

from ..laws.common import INV_PLANE_FADE2, LEAD_EPS, PLANE_EPS, TINY
from ..laws.depth_only import SIGN_EPS
from ..laws.hybrid import COS_BREAK, SIN_BREAK
from ..laws.registry import LAWS as _TABLE
from ..laws.rft3d import C1, C2, C3, TANGENT_EPS, VERTICAL_BAND
from ..params import (P_HYB_E0, P_HYB_E1, P_HYB_E2, P_HYB_KF, P_HYB_KS, P_HYB_PAR_H, P_HYB_PAR_H_FRAC, P_HYB_PERP_H,
                      P_HYB_RATIO, P_HYB_W, P_WATER_DEPTH, P_WATER_DRAG, P_WATER_SKIN, P_WET_FCAP, P_WET_K, P_WET_VBASE,
                      P_WET_VCAP)


def _dot(a, b):
    return jnp.sum(a * b, axis=-1)


def lead_weight(n_dot_m):
    """:func:`mjrft.laws.common.lead_weight`: ``clip(0.5 + n.m / (2 LEAD_EPS), 0, 1)``."""
    return jnp.clip(0.5 + n_dot_m * (0.5 / LEAD_EPS), 0.0, 1.0)


def motion_plane(n, m):
    """:func:`mjrft.laws.common.motion_plane`: unit horizontal axis r (k, 2) of each element's plane of motion."""
    mx, my = m[:, 0], m[:, 1]
    q = jnp.minimum(1.0, (mx * mx + my * my) * INV_PLANE_FADE2)
    pw = PLANE_EPS * (1.0 - q) * (1.0 - q)
    hx = mx + pw * n[:, 0]
    hy = my + pw * n[:, 1]
    h2 = hx * hx + hy * hy
    use = h2 > TINY * TINY
    inv = 1.0 / jnp.sqrt(jnp.where(use, h2, 1.0))
    return jnp.where(use, hx * inv, 1.0), jnp.where(use, hy * inv, 0.0)


def rft(depth, n, m, p, speed=None):
    """Li 2013 RFT in each element's vertical plane of motion (:mod:`mjrft.laws.rft`)."""
    nx, ny, nz = n[:, 0], n[:, 1], n[:, 2]
    mx, my, mz = m[:, 0], m[:, 1], m[:, 2]
    lw = lead_weight(nx * mx + ny * my + nz * mz)
    rx, ry = motion_plane(n, m)
    vr = mx * rx + my * ry
    ivn = 1.0 / jnp.sqrt(jnp.maximum(vr * vr + mz * mz, TINY * TINY))
    cg = vr * ivn
    sg = -mz * ivn
    nr = nx * rx + ny * ry
    w2 = nr * nr + nz * nz
    iw = 1.0 / jnp.maximum(w2, TINY * TINY)
    c2 = (nz * nz - nr * nr) * iw
    s2 = -2.0 * nr * nz * iw
    az = p[..., 0] + p[..., 1] * c2 + p[..., 2] * (s2 * cg + c2 * sg) + p[..., 3] * sg + p[..., 4] * (c2 * sg - s2 * cg)
    ax = p[..., 5] * (c2 * cg - s2 * sg) + p[..., 6] * cg + p[..., 7] * (c2 * cg + s2 * sg) + p[..., 8] * s2
    k = jnp.where(w2 >= TINY * TINY, lw * jnp.sqrt(w2) * jnp.maximum(depth, 0.0), 0.0)
    return jnp.stack([-ax * rx * k, -ax * ry * k, az * k], axis=-1)


def _poly(c, x1, x2, x3):
    return (c[0] + c[1] * x1 + c[2] * x2 + c[3] * x3 + c[4] * x1 * x1 + c[5] * x2 * x2 + c[6] * x3 * x3
            + c[7] * x1 * x2 + c[8] * x2 * x3 + c[9] * x3 * x1 + c[10] * x1 ** 3 + c[11] * x2 ** 3 + c[12] * x3 ** 3
            + c[13] * x1 * x2 * x2 + c[14] * x2 * x1 * x1 + c[15] * x2 * x3 * x3 + c[16] * x3 * x2 * x2
            + c[17] * x3 * x1 * x1 + c[18] * x1 * x3 * x3 + c[19] * x1 * x2 * x3)


def _response(sb, cb, sg, cgm, sp, cp):
    """(alpha_r, alpha_theta, alpha_z) of 3D-RFT's generic fit (:func:`mjrft.laws.rft3d._response`) from the sines and
    cosines of beta, gamma and psi."""
    x3 = cp * cgm * sb + sg * cb
    f1 = _poly(C1, sg, cb, x3)
    f2 = _poly(C2, sg, cb, x3)
    f3 = _poly(C3, sg, cb, x3)
    return f1 * sb * cp + f2 * cgm, f1 * sb * sp, -f1 * cb - f2 * sg - f3


def rft3d_generic(n, m):
    """3D-RFT's dimensionless generic response (k, 3) in the world frame (:func:`mjrft.laws.rft3d.rft3d_generic`).

    The numba law takes the angles with ``acos`` and ``atan`` and then their sines and cosines; here those come
    from the vectors themselves (equal in exact arithmetic for unit ``n``, ``m``): ``beta``'s from ``n_z`` and
    ``|n_h|``, ``gamma``'s from ``m . r`` and ``|m x r|``, ``psi``'s from ``n . r`` and ``n . theta``. No
    transcendental function is left, and no ``acos`` of a cosine within rounding of 1, which turns one ulp into
    ``sqrt(2 ulp)`` of angle (exactly horizontal motion: 1.5e-8 rad in float64, 3.5e-4 rad in float32)."""
    nx, ny, nz = n[:, 0], n[:, 1], n[:, 2]
    mx, my, mz = m[:, 0], m[:, 1], m[:, 2]
    rx, ry = motion_plane(n, m)
    tx, ty = -ry, rx
    nr = nx * rx + ny * ry
    nt = nx * tx + ny * ty
    nh = jnp.sqrt(nx * nx + ny * ny)
    cz = jnp.clip(nz, -1.0, 1.0)
    # beta's two branches (normal tilted up / down): beta_up = -+acos(n_z), beta_dn = +-pi -+ acos(n_z)
    sb_up = jnp.where(nr >= 0.0, -nh, nh)
    # gamma = acos(m . r), negative for upward motion
    cg = mx * rx + my * ry
    cross = mx * ry - my * rx
    sg = jnp.sqrt(mz * mz + cross * cross)
    hyp = jnp.sqrt(cg * cg + sg * sg)
    inv = 1.0 / jnp.where(hyp > 0.0, hyp, 1.0)
    cg = jnp.where(hyp > 0.0, cg * inv, 1.0)
    sg = jnp.where(mz > 0.0, -sg, sg) * inv
    # psi = atan(n_theta / n_r): 0 for a horizontal face, +-pi/2 edge-on to the plane
    side = jnp.abs(nr) < TINY * nh
    flat = nh < TINY
    q = jnp.sqrt(nr * nr + nt * nt)
    iq = 1.0 / jnp.where(flat | side, 1.0, q)
    sp = jnp.where(flat, 0.0, jnp.where(side, jnp.where(jnp.signbit(nt), -1.0, 1.0), jnp.sign(nr) * nt * iq))
    cp = jnp.where(flat, 1.0, jnp.where(side, 0.0, jnp.abs(nr) * iq))
    w_up = jnp.where(cz >= 0.0, 1.0, jnp.maximum(0.0, 1.0 + cz / VERTICAL_BAND))
    r1, t1, z1 = _response(sb_up, cz, sg, cg, sp, cp)
    r2, t2, z2 = _response(-sb_up, -cz, sg, cg, sp, cp)
    ar = w_up * r1 + (1.0 - w_up) * r2
    at = w_up * t1 + (1.0 - w_up) * t2
    az = w_up * z1 + (1.0 - w_up) * z2
    return jnp.stack([ar * rx + at * tx, ar * ry + at * ty, az], axis=-1)


def rft3d(depth, n, m, p, speed=None):
    """Three-dimensional RFT (:mod:`mjrft.laws.rft3d`: no tension, friction cap, tangential reflection)."""
    lw = lead_weight(_dot(n, m))
    g = rft3d_generic(n, m)
    an = _dot(g, n)
    t = g - an[:, None] * n
    an = jnp.minimum(an, 0.0)
    mn = _dot(m, n)
    s = m - mn[:, None] * n
    sl = jnp.sqrt(_dot(s, s))
    sl_safe = jnp.where(sl > TINY, sl, 1.0)
    along = _dot(t, s) / sl_safe
    k_ref = jnp.where((sl > TINY) & (along > 0.0), 2.0 * along * jnp.minimum(1.0, sl / TANGENT_EPS) / sl_safe, 0.0)
    t = t - k_ref[:, None] * s
    tl = jnp.sqrt(_dot(t, t))
    cap = jnp.where(tl > TINY, jnp.minimum(1.0, p[..., 10] * jnp.abs(an) / jnp.where(tl > TINY, tl, 1.0)), 1.0)
    k = jnp.where((depth > 0.0) & (lw > 0.0), p[..., 9] * depth * lw, 0.0)
    return (an[:, None] * n + cap[:, None] * t) * k[:, None]


def _smooth_sign(x, eps):
    return jnp.clip(x / eps, -1.0, 1.0)


def depth_only(depth, n, m, p, speed=None):
    """The flat-plate (depth-only) baseline (:mod:`mjrft.laws.depth_only`)."""
    nx, ny, nz = n[:, 0], n[:, 1], n[:, 2]
    mx, my, mz = m[:, 0], m[:, 1], m[:, 2]
    lw = lead_weight(nx * mx + ny * my + nz * mz)
    az = jnp.where(mz < 0.0, p[..., 12], p[..., 13])
    fz = -_smooth_sign(mz, SIGN_EPS) * az * jnp.abs(nz)
    h = jnp.sqrt(mx * mx + my * my)
    moving = h > 0.0
    h_safe = jnp.where(moving, h, 1.0)
    rx, ry = mx / h_safe, my / h_safe
    fh = jnp.where(moving, -_smooth_sign(h, SIGN_EPS) * p[..., 14] * jnp.abs(nx * rx + ny * ry), 0.0)
    k = jnp.where((depth > 0.0) & (lw > 0.0), lw * depth, 0.0)
    return jnp.stack([fh * rx * k, fh * ry * k, fz * k], axis=-1)


def _speed_of(law: str, speed):
    if speed is None:
        raise TypeError(f"law {law!r} is rate-dependent: pass each element's speed (m/s) as speed=")
    return speed


def wet_speed_factor(speed, p):
    """:func:`mjrft.laws.wet.wet_speed_factor`: ``1 + (eps_v / dv) (v - v_base)``, held at its value at ``v_cap``
    from there on (also for an infinite speed); a NaN or negative speed counts as 0."""
    line = 1.0 + p[..., P_WET_K] * (jnp.where(speed > 0.0, speed, 0.0) - p[..., P_WET_VBASE])
    return jnp.where(speed >= p[..., P_WET_VCAP], p[..., P_WET_FCAP], line)


def wet(depth, n, m, p, speed=None):
    """SGRFT saturated sand (:mod:`mjrft.laws.wet`): Li RFT of the medium times the speed factor of each element's
    real ``speed``."""
    return rft(depth, n, m, p) * wet_speed_factor(_speed_of("wet", speed), p)[..., None]


def water(depth, n, m, p, speed=None):
    """The free-water layer's drag (:func:`mjrft.laws.wet.water_stress`): ``-C rho_w v^2 max(0, n.m) w m`` for an
    element of the layer (``-water depth < depth``), ``w`` its fades over the skin below the water surface and
    into the sand; zero outside and without a layer."""
    speed = _speed_of("water", speed)
    hw = p[..., P_WATER_DEPTH]
    skin = p[..., P_WATER_SKIN]
    h = -depth
    s = jnp.minimum(skin, hw)
    s_safe = jnp.where(s > 0.0, s, 1.0)
    w = jnp.minimum((hw - h) / s_safe, (h + s) / s_safe)  # fade below the water surface / into the sand
    proj = _dot(n, m)
    on = (hw > 0.0) & (skin > 0.0) & (w > 0.0) & ~(proj <= 0.0)
    k = -p[..., P_WATER_DRAG] * speed * speed * proj * jnp.minimum(w, 1.0)
    return jnp.where(on[..., None], k[..., None] * m, 0.0)


def hybrid(depth, n, m, p, speed=None):
    """The curved-leg hybrid law per thin-leg element (:func:`mjrft.laws.hybrid.hybrid_stress`): the Coulomb
    wedge's ``C_perp(d)`` (its quadratic in the depth below one leg width), the bar-drag fit's ``F_perp`` and
    ``F_par`` of ``sin psi = |n.m|``, the density factors on the horizontal and vertical parts.

    ``cos psi`` is the length of the tangential motion ``m - (m.n) n``, which for unit vectors equals the numba
    law's ``sqrt(1 - sin^2 psi)``; the square root's form loses half the digits near face-on motion (in float32,
    up to 4e-4 of ``C_par`` when the rounded ``n.m`` is one ulp below 1), this one does not."""
    c = _dot(n, m)
    lw = lead_weight(c)
    w = p[..., P_HYB_W]
    sp = jnp.minimum(1.0, jnp.abs(c))
    t = m - c[:, None] * n
    tl = jnp.sqrt(_dot(t, t))
    cp = tl  # cos psi = |m - (m.n) n| = sqrt(1 - sin^2 psi) (unit n, m), without the cancellation near face-on motion
    x = depth - w
    cperp = jnp.where(depth <= w, p[..., P_HYB_E0] * depth * depth,
                      p[..., P_HYB_E0] * w * w + p[..., P_HYB_E1] * w * x + p[..., P_HYB_E2] * x * x)
    cperp_h = p[..., P_HYB_PERP_H] * depth * w
    cpar = p[..., P_HYB_RATIO] * cperp
    cpar_h = p[..., P_HYB_PAR_H_FRAC] * cpar + p[..., P_HYB_PAR_H] * depth * w
    fperp = cperp_h + (cperp - cperp_h) * sp
    fpar = jnp.where(sp <= SIN_BREAK, cpar_h + (cpar - cpar_h) * sp / SIN_BREAK, cpar * cp / COS_BREAK)
    t = jnp.where((tl > TINY)[:, None], t / jnp.where(tl > TINY, tl, 1.0)[:, None], 0.0)
    k = jnp.where((depth > 0.0) & (lw > 0.0), lw / w, 0.0)
    kf = k * p[..., P_HYB_KF]
    ks = k * p[..., P_HYB_KS]
    return jnp.stack([-kf * (fperp * n[:, 0] + fpar * t[:, 0]), -kf * (fperp * n[:, 1] + fpar * t[:, 1]),
                      -ks * (fperp * n[:, 2] + fpar * t[:, 2])], axis=-1)


_missing = [f"{law.name} ({law.jax})" for law in _TABLE if law.jax is not None and not callable(globals().get(law.jax))]
if _missing:
    raise RuntimeError(f"mjrft.laws.registry.LAWS names JAX twins that mjrft.mjx.laws does not define: "
                       f"{', '.join(_missing)}")
#: law name -> JAX stress function (the laws whose entry in the table names a twin)
LAWS = {law.name: globals()[law.jax] for law in _TABLE if law.jax is not None}
#: the laws the JAX path does not model, and why (the error names the entry)
UNSUPPORTED = {law.name: law.no_jax for law in _TABLE if law.jax is None}


def law_function(name: str):
    """The JAX stress function of a law name; a law without a JAX twin raises naming why and what is ported."""
    if name in LAWS:
        return LAWS[name]
    why = UNSUPPORTED.get(name, "it is not a law of mjrft")
    raise NotImplementedError(f"law {name!r} has no JAX version ({why}); mjrft.mjx supports "
                              f"{', '.join(LAWS)}")


__all__ = ["LAWS", "UNSUPPORTED", "depth_only", "hybrid", "law_function", "rft", "rft3d", "water", "wet",
           "wet_speed_factor"]
