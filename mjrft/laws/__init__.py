"""Force laws: pure, vectorised functions of element state (no MuJoCo).

Every law has the same signature::

    forces = law(depth, normal, velocity, area, medium="poppy_cp")

with ``depth`` (n,) in m, POSITIVE below the free surface (the papers' |z|; elements at or above
the surface feel nothing), ``normal`` (n, 3) outward normals, ``velocity`` (n, 3) in m/s and
``area`` (n,) in m^2, all in the world frame with z up; it returns forces (n, 3) in N. The dry laws
are rate-independent: only the direction of the velocity matters, and a zero velocity gives zero
force (the coupler's rest regularisation, not the law, decides what a resting element feels).
With ``inertial=True`` they add the dry inertial regime above the critical speed v_c
(:mod:`mjrft.laws.inertial`, Zhang et al. DynaRoACH paper; off by default).
"""

from __future__ import annotations

import numpy as np

from ..media import get_medium
from .dispatch import as_elements, element_stress, evaluate
from .inertial import INERTIAL_DRAG, add_inertial, set_inertial
from .registry import DRY_LAWS, LAW_IDS, get_law, parameter_vector
from .rft3d import rft3d_generic


def law_id(name: str) -> int:
    """The kernel id of a law name (:mod:`mjrft.laws.registry`); unknown names list the valid choices."""
    return get_law(name).id


def apply_law(name, depth, normal, velocity, area, medium="poppy_cp", *, inertial=False,
              inertial_drag=INERTIAL_DRAG):
    """Evaluate the law called ``name`` on the given elements; see the module docstring.

    ``inertial=True`` (dry laws ``rft``, ``rft3d``, ``depth_only`` only) adds the inertial regime with
    coefficient ``inertial_drag`` (:mod:`mjrft.laws.inertial`)."""
    law = get_law(name)
    med = get_medium(medium)
    if inertial and not law.dry:
        raise ValueError(f"inertial=True is an option of the dry laws ({', '.join(DRY_LAWS)}), not of law {name!r}")
    depth, normal, velocity, area = as_elements(depth, normal, velocity, area)
    out = np.empty((depth.shape[0], 3))
    p = parameter_vector(med)
    evaluate(law.id, depth, normal, velocity, area, p, out)
    if inertial:
        add_inertial(depth, normal, velocity, area, set_inertial(p, med, inertial_drag), out)
    return out


def rft(depth, normal, velocity, area, medium="poppy_cp", *, inertial=False):
    """Li 2013 RFT in each element's vertical plane of motion (:mod:`mjrft.laws.rft`); ``inertial``: add the
    inertial regime (:mod:`mjrft.laws.inertial`)."""
    return apply_law("rft", depth, normal, velocity, area, medium, inertial=inertial)


def rft3d(depth, normal, velocity, area, medium="poppy_cp", *, inertial=False):
    """Agarwal 2023 3D-RFT (:mod:`mjrft.laws.rft3d`); ``inertial``: add the inertial regime."""
    return apply_law("rft3d", depth, normal, velocity, area, medium, inertial=inertial)


def depth_only(depth, normal, velocity, area, medium="poppy_cp", *, inertial=False):
    """Flat-plate baseline (:mod:`mjrft.laws.depth_only`); ``inertial``: add the inertial regime."""
    return apply_law("depth_only", depth, normal, velocity, area, medium, inertial=inertial)


def wet(depth, normal, velocity, area, medium="sea_sand_saturated"):
    """SGRFT saturated wet sand: Li RFT x a speed factor of each element's speed (:mod:`mjrft.laws.wet`)."""
    return apply_law("wet", depth, normal, velocity, area, medium)


def water(depth, normal, velocity, area, medium="sea_sand_saturated"):
    """Drag of the free-water layer above the sand, ``depth < 0`` (:mod:`mjrft.laws.wet`); needs ``water_depth``."""
    return apply_law("water", depth, normal, velocity, area, medium)


def hybrid(depth, normal, velocity, area, medium="poppy_cp"):
    """Hybrid curved-leg model per thin-leg element (:mod:`mjrft.laws.hybrid`)."""
    return apply_law("hybrid", depth, normal, velocity, area, medium)


def rft3d_alpha_generic(normal, velocity):
    """3D-RFT generic (dimensionless) response for unit normals/velocities, shape (n, 3)."""
    n = np.atleast_2d(np.asarray(normal, float))
    v = np.atleast_2d(np.asarray(velocity, float))
    n = n / np.linalg.norm(n, axis=1, keepdims=True)
    v = v / np.linalg.norm(v, axis=1, keepdims=True)
    return np.array([rft3d_generic(*a, *b) for a, b in zip(n, v)])


LAWS = {"rft": rft, "rft3d": rft3d, "depth_only": depth_only, "wet": wet, "water": water, "hybrid": hybrid}

__all__ = ["LAWS", "LAW_IDS", "apply_law", "depth_only", "element_stress", "hybrid", "law_id", "rft", "rft3d",
           "rft3d_alpha_generic", "water", "wet"]
