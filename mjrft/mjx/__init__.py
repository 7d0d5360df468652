"""mjrft on the GPU: the granular wrench as pure JAX functions of MJX's ``Model`` / ``Data``.

>>> import jax, mujoco, mjrft.mjx
>>> sand = mjrft.mjx.Sand(model, floor="auto")        # a mujoco.MjModel; GranularTerrain's arguments
>>> mx, step = sand.put_model(), jax.jit(sand.step)   # step(mx, d, state) -> (d, state)

:mod:`mjrft.mjx.terrain` (:class:`Sand`, :class:`SandState`), :mod:`mjrft.mjx.laws` (the JAX force laws),
:mod:`mjrft.mjx.forces` (an element's whole force: the inertial regime, water drag, buoyancy, regions and their
blending), :mod:`mjrft.mjx.surface` (the height field's surface, the regions' weights), :mod:`mjrft.mjx.memory`
(the rest memory and the solidify option), :mod:`mjrft.mjx.ground` (the ground memory: footprints, ridges,
packing and the hybrid law's wake per world), :mod:`mjrft.mjx.guards` (the stability, chatter and range checks every
step runs, :func:`~mjrft.mjx.guards.flags`), :mod:`mjrft.mjx.compare` (checking a JAX terrain against the CPU path on
recorded states) and :mod:`mjrft.mjx.integrator` (:func:`step`: MJX's step as MuJoCo's C library integrates clamped
servos, the rigid twin of ``Sand.step``), and :mod:`mjrft.mjx.sand_env` (:func:`on_sand`: a MuJoCo Playground
environment on sand).
Needs the optional extra ``mjrft[mjx]`` (JAX and ``mujoco-mjx``); the rest of mjrft does not import it.
The GPU guide is docs/gpu.md.
"""

try:
    import jax  # noqa: F401
    from mujoco import mjx  # noqa: F401
except ImportError as exc:  # say which extra brings it
    raise ImportError(f"mjrft.mjx needs JAX and MJX: pip install 'mjrft[mjx]' (Python >= 3.11; docs/gpu.md); "
                      f"{exc}") from exc

from . import compare, guards  # noqa: E402
from .integrator import integrate, step  # noqa: E402
from .laws import LAWS, UNSUPPORTED  # noqa: E402
from .sand_env import SandEnv, on_sand  # noqa: E402
from .terrain import Sand, SandState, resting_load  # noqa: E402

__all__ = ["LAWS", "UNSUPPORTED", "Sand", "SandEnv", "SandState", "compare", "guards", "integrate", "on_sand",
           "resting_load", "step"]
