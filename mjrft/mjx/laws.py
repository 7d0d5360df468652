"""The force laws in JAX: pure, branch-free functions of element arrays, the twins of :mod:`mjrft.laws`.

Every function here has the signature ``stress(depth, n, m, p) -> (k, 3)``: ``depth`` (k,) in m, positive
below the surface, ``n`` (k, 3) unit outward normals, ``m`` (k, 3) unit (regularised) motion directions,
``p`` the medium's parameter vector (:func:`mjrft.laws.registry.parameter_vector`, layout :mod:`mjrft.params`). The
result is the stress (Pa) on each element; the caller multiplies by area and mobilisation. They follow
their numba twins line for line (the same smoothing constants, the same choices, documented there), with
``jnp.where`` in place of each branch, so they run under ``jit`` and ``vmap`` on any JAX device and in
float32 or float64 (whatever arrays they are given).

Ported: ``rft`` (:func:`mjrft.laws.rft.rft_stress_batch`), ``rft3d`` (:func:`mjrft.laws.rft3d.rft3d_stress`)
and ``depth_only`` (:func:`mjrft.laws.depth_only.depth_only_stress`). Which function is a law's twin, and why a
law has none, the table of laws says (:data:`mjrft.laws.registry.LAWS`, each entry's ``jax`` and ``no_jax``):
:data:`LAWS` and :data:`UNSUPPORTED` are built from it.
"""

from __future__ import annotations

import math

import jax.numpy as jnp

from ..laws.common import INV_PLANE_FADE2, LEAD_EPS, PLANE_EPS, TINY
from ..laws.depth_only import SIGN_EPS
from ..laws.registry import LAWS as _TABLE
from ..laws.rft3d import C1, C2, C3, TANGENT_EPS, VERTICAL_BAND


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


def rft(depth, n, m, p):
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
    az = p[0] + p[1] * c2 + p[2] * (s2 * cg + c2 * sg) + p[3] * sg + p[4] * (c2 * sg - s2 * cg)
    ax = p[5] * (c2 * cg - s2 * sg) + p[6] * cg + p[7] * (c2 * cg + s2 * sg) + p[8] * s2
    k = jnp.where(w2 >= TINY * TINY, lw * jnp.sqrt(w2) * jnp.maximum(depth, 0.0), 0.0)
    return jnp.stack([-ax * rx * k, -ax * ry * k, az * k], axis=-1)


def _poly(c, x1, x2, x3):
    return (c[0] + c[1] * x1 + c[2] * x2 + c[3] * x3 + c[4] * x1 * x1 + c[5] * x2 * x2 + c[6] * x3 * x3
            + c[7] * x1 * x2 + c[8] * x2 * x3 + c[9] * x3 * x1 + c[10] * x1 ** 3 + c[11] * x2 ** 3 + c[12] * x3 ** 3
            + c[13] * x1 * x2 * x2 + c[14] * x2 * x1 * x1 + c[15] * x2 * x3 * x3 + c[16] * x3 * x2 * x2
            + c[17] * x3 * x1 * x1 + c[18] * x1 * x3 * x3 + c[19] * x1 * x2 * x3)


def _response(beta, gamma, psi):
    """(alpha_r, alpha_theta, alpha_z) of 3D-RFT's generic fit (:func:`mjrft.laws.rft3d._response`)."""
    sb, cb = jnp.sin(beta), jnp.cos(beta)
    sg, cgm = jnp.sin(gamma), jnp.cos(gamma)
    sp, cp = jnp.sin(psi), jnp.cos(psi)
    x3 = cp * cgm * sb + sg * cb
    f1 = _poly(C1, sg, cb, x3)
    f2 = _poly(C2, sg, cb, x3)
    f3 = _poly(C3, sg, cb, x3)
    return f1 * sb * cp + f2 * cgm, f1 * sb * sp, -f1 * cb - f2 * sg - f3


def rft3d_generic(n, m):
    """3D-RFT's dimensionless generic response (k, 3) in the world frame (:func:`mjrft.laws.rft3d.rft3d_generic`)."""
    nx, ny, nz = n[:, 0], n[:, 1], n[:, 2]
    rx, ry = motion_plane(n, m)
    tx, ty = -ry, rx
    nr = nx * rx + ny * ry
    cz = jnp.clip(nz, -1.0, 1.0)
    acz = jnp.arccos(cz)
    b_up = jnp.where(nr >= 0.0, -acz, acz)
    b_dn = jnp.where(nr >= 0.0, math.pi - acz, -math.pi + acz)
    gamma = jnp.arccos(jnp.clip(m[:, 0] * rx + m[:, 1] * ry, -1.0, 1.0))
    gamma = jnp.where(m[:, 2] > 0.0, -gamma, gamma)
    nt = nx * tx + ny * ty
    nh = jnp.sqrt(nx * nx + ny * ny)
    side = jnp.abs(nr) < TINY * nh
    psi = jnp.where(nh < TINY, 0.0,
                    jnp.where(side, jnp.copysign(0.5 * math.pi, nt),
                              jnp.arctan(nt / jnp.where(side, 1.0, nr))))
    w_up = jnp.where(cz >= 0.0, 1.0, jnp.maximum(0.0, 1.0 + cz / VERTICAL_BAND))
    r1, t1, z1 = _response(b_up, gamma, psi)
    r2, t2, z2 = _response(b_dn, gamma, psi)
    ar = w_up * r1 + (1.0 - w_up) * r2
    at = w_up * t1 + (1.0 - w_up) * t2
    az = w_up * z1 + (1.0 - w_up) * z2
    return jnp.stack([ar * rx + at * tx, ar * ry + at * ty, az], axis=-1)


def rft3d(depth, n, m, p):
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
    cap = jnp.where(tl > TINY, jnp.minimum(1.0, p[10] * jnp.abs(an) / jnp.where(tl > TINY, tl, 1.0)), 1.0)
    k = jnp.where((depth > 0.0) & (lw > 0.0), p[9] * depth * lw, 0.0)
    return (an[:, None] * n + cap[:, None] * t) * k[:, None]


def _smooth_sign(x, eps):
    return jnp.clip(x / eps, -1.0, 1.0)


def depth_only(depth, n, m, p):
    """The flat-plate (depth-only) baseline (:mod:`mjrft.laws.depth_only`)."""
    nx, ny, nz = n[:, 0], n[:, 1], n[:, 2]
    mx, my, mz = m[:, 0], m[:, 1], m[:, 2]
    lw = lead_weight(nx * mx + ny * my + nz * mz)
    az = jnp.where(mz < 0.0, p[12], p[13])
    fz = -_smooth_sign(mz, SIGN_EPS) * az * jnp.abs(nz)
    h = jnp.sqrt(mx * mx + my * my)
    moving = h > 0.0
    h_safe = jnp.where(moving, h, 1.0)
    rx, ry = mx / h_safe, my / h_safe
    fh = jnp.where(moving, -_smooth_sign(h, SIGN_EPS) * p[14] * jnp.abs(nx * rx + ny * ry), 0.0)
    k = jnp.where((depth > 0.0) & (lw > 0.0), lw * depth, 0.0)
    return jnp.stack([fh * rx * k, fh * ry * k, fz * k], axis=-1)


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


__all__ = ["LAWS", "UNSUPPORTED", "law_function", "rft", "rft3d", "depth_only"]
