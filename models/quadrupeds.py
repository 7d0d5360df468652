"""Two third-party quadrupeds vendored under ``third_party/`` with their licences, and an open-loop trot for each.

* **ANYmal C** (``third_party/anybotics_anymal_c/``, MuJoCo Menagerie, BSD-3-Clause): 45 kg, 12 position
  servos (kp 100, force range +-80 N m), collision primitives only; its 2 ms default timestep. ``ctrl = 0`` holds
  the legs straight, the model's own initial pose.
* **dm_control's quadruped** (``third_party/dm_quadruped/``, dm_control suite, Apache-2.0): 107 kg of capsules and
  ellipsoids with tendon-coupled legs (an equality constraint per leg) and filtered servos on yaw, lift and extend;
  its 5 ms timestep. :func:`dm_quadruped_model` applies what dm_control's ``quadruped.make_model`` does for the walk
  and run tasks (walls, ball, target, height field and rangefinders removed), so the robot stands on the plane.

:func:`trot_ctrl` is a plain open-loop trot around the standing controls: diagonal legs in antiphase, each leg
lifting in its swing half and sweeping fore and aft. It is a test controller (no feedback, not from either
robot's makers).
"""

from __future__ import annotations

import os

import mujoco
import numpy as np

_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "third_party")
ANYMAL_C_DIR = os.path.join(_DIR, "anybotics_anymal_c")
ANYMAL_C = os.path.join(ANYMAL_C_DIR, "scene.xml")
DM_QUADRUPED_DIR = os.path.join(_DIR, "dm_quadruped")
DM_QUADRUPED = os.path.join(DM_QUADRUPED_DIR, "quadruped.xml")

#: the feet: the bodies that carry a standing robot (ANYmal C's foot spheres are on its shanks)
FEET = {"anymal_c": ("LF_SHANK", "RF_SHANK", "LH_SHANK", "RH_SHANK"),
        "dm_quadruped": ("toe_front_left", "toe_front_right", "toe_back_right", "toe_back_left")}


def anymal_c_model() -> mujoco.MjModel:
    """ANYmal C on Menagerie's scene (a plane ``floor``), at its 2 ms timestep."""
    return mujoco.MjModel.from_xml_path(ANYMAL_C)


def dm_quadruped_model() -> mujoco.MjModel:
    """dm_control's quadruped as its walk task builds it (``quadruped.make_model(walls_and_ball=False,
    terrain=False, rangefinders=False)``), at its 5 ms timestep."""
    spec = mujoco.MjSpec.from_file(DM_QUADRUPED)
    for name in ("wall_px", "wall_py", "wall_nx", "wall_ny", "terrain"):
        spec.delete(spec.geom(name))
    spec.delete(spec.body("ball"))
    spec.delete(spec.site("target"))
    for sensor in list(spec.sensors):
        if sensor.type == mujoco.mjtSensor.mjSENS_RANGEFINDER:
            spec.delete(sensor)
    return spec.compile()


MODELS = {"anymal_c": anymal_c_model, "dm_quadruped": dm_quadruped_model}


def trot_ctrl(name: str, model: mujoco.MjModel, t: float, freq: float = 1.5) -> np.ndarray:
    """Open-loop trot controls of robot ``name`` (a key of :data:`MODELS`) at time ``t`` (s): the diagonal pairs
    in antiphase at ``freq`` Hz, each leg lifting in the swing half of its cycle and sweeping fore and aft.

    ANYmal C: hip flexion (HFE) sweeping +-0.5 rad, knee (KFE) flexing by up to 0.8 rad in swing (its legs are
    straight at ``ctrl = 0``; the knees of the front and hind legs bend opposite ways); it faces -x (the model's base
    is turned 180 degrees about z). dm_control's quadruped: each hip's yaw sweeping +-0.5 rad, signed by the leg's
    side so that the stance legs push towards -x and it walks towards +x (its front), and ``lift`` up to 0.6 in
    swing (its actuators' units); ``extend`` stays 0."""
    if name == "anymal_c":  # actuators LF, RF, LH, RH x (HAA, HFE, KFE); diagonals LF+RH, RF+LH
        phase = 2 * np.pi * freq * t + np.array([0.0, np.pi, np.pi, 0.0])
        front = np.array([1.0, 1.0, -1.0, -1.0])
        ctrl = np.zeros((4, 3))
        ctrl[:, 1] = -0.5 * np.cos(phase) * front
        ctrl[:, 2] = -0.8 * np.maximum(np.sin(phase), 0.0) * front
        return ctrl.ravel()
    if name == "dm_quadruped":  # actuators FL, FR, BR, BL x (yaw, lift, extend); diagonals FL+BR, FR+BL
        phase = 2 * np.pi * freq * t + np.array([0.0, np.pi, 0.0, np.pi])
        side = np.array([1.0, -1.0, -1.0, 1.0])  # the hips point at 45, -45, -135 and 135 degrees
        ctrl = np.zeros((4, 3))
        ctrl[:, 0] = -0.5 * side * np.cos(phase)
        ctrl[:, 1] = 0.6 * np.maximum(np.sin(phase), 0.0)
        return ctrl.ravel()
    raise ValueError(f"no trot for robot {name!r}; the robots are {sorted(MODELS)}")
