"""A diverged simulation is named, never silently restarted: MuJoCo's own resets and the kernel's non-finite status.

MuJoCo resets ``mjData`` when it finds a bad (non-finite or huge) position, velocity or acceleration and counts
it in ``data.warning``; :func:`mujoco_resets` reads the counters and :func:`mujoco_reset_error` names the body.
:func:`nonfinite_error` names the body and time of a kernel status (a non-finite granular force or state), raised
before anything is written to ``mjData``. :func:`whole_steps` refuses a step count that is not a whole number.
"""

from __future__ import annotations

import mujoco
import numpy as np

from . import kernel
from .errors import NonFiniteError

_RESET_WARNINGS = (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL, mujoco.mjtWarning.mjWARN_BADQACC)
_RESET_INDEX = tuple(int(w) for w in _RESET_WARNINGS)


def mujoco_resets(data: mujoco.MjData) -> int:
    """How many times MuJoCo found a bad (non-finite or huge) position, velocity or acceleration in
    ``data`` and reset it (its warning counters; ``mj_resetData`` clears them)."""
    return reset_count(data.warning.number)


def reset_count(numbers: np.ndarray) -> int:
    """:func:`mujoco_resets` from ``data.warning.number`` (a view of the counters that stays valid while
    ``data`` lives: the terrain keeps it for the data it is bound to, ~0.5 us a read)."""
    a, b, c = _RESET_INDEX
    return int(numbers[a]) + int(numbers[b]) + int(numbers[c])


def mujoco_reset_error(model: mujoco.MjModel, data: mujoco.MjData, since: str) -> NonFiniteError:
    """The :class:`NonFiniteError` for a simulation that MuJoCo reset after it diverged, naming the body."""
    for w in _RESET_WARNINGS:
        if data.warning[w].number:
            info = int(data.warning[w].lastinfo)
            if w == mujoco.mjtWarning.mjWARN_BADQPOS:
                joint = int(np.searchsorted(model.jnt_qposadr, info, side="right")) - 1
                body = int(model.jnt_bodyid[max(joint, 0)]) if model.njnt else 0
                what = f"position (qpos[{info}])"
            else:
                body = int(model.dof_bodyid[info]) if 0 <= info < model.nv else 0
                what = ("velocity" if w == mujoco.mjtWarning.mjWARN_BADQVEL else "acceleration") + f" (dof {info})"
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or f"#{body}"
            break
    return NonFiniteError(f"the simulation diverged: MuJoCo found a non-finite or huge {what} on body '{name}' "
                          f"{since} and reset the state (its time is now {data.time:.6g} s); the diverged state is "
                          "lost. Reduce the timestep, or check the model and the forces applied to it")


def whole_steps(nstep) -> int:
    """``nstep`` as a count of physics steps (an integer >= 0, or a float equal to one); anything else raises a
    ``ValueError`` naming it (``step(data, 1.5)`` would otherwise run one step)."""
    if isinstance(nstep, (bool, np.bool_)) or not isinstance(nstep, (int, float, np.integer, np.floating)):
        raise ValueError(f"nstep must be a whole number of steps >= 0, got {nstep!r}")
    if not float(nstep).is_integer() or nstep < 0:
        raise ValueError(f"nstep must be a whole number of steps >= 0, got {nstep!r}")
    return int(nstep)


def nonfinite_error(model: mujoco.MjModel, status: int, body: int, time: float) -> NonFiniteError:
    """The :class:`NonFiniteError` for a kernel ``status`` (``kernel.BAD_FORCE`` or ``kernel.BAD_STATE``) on ``body``."""
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or f"#{body}"
    what = "granular force" if status == kernel.BAD_FORCE else "state (position or velocity)"
    return NonFiniteError(f"non-finite {what} on body '{name}' at t = {time:.6g} s; nothing was written to mjData")
