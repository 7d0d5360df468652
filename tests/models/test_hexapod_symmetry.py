"""Mirror symmetry of the free-body hexapod: model, coupler and tripod gait.

The RHex-class model is symmetric about its sagittal plane and the tripods are mirror images
(A = lf, rm, lr; B = rf, lm, rr). Starting on the gait's pose with tripod A leading (``phase=0``)
or with tripod B leading (``phase=0.5``) are mirror images of each other, so the two runs must give
mirrored paths: y -> -y and yaw -> -yaw. The heading the open-loop tripod takes in its first
strides (tens of degrees with C-legs) comes from which tripod carries the body first, not from a
left/right asymmetry of the simulation; this test keeps it that way.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("imageio")  # gymnasium.envs.mujoco needs it (gymnasium[mujoco])

import mujoco  # noqa: E402

import mjrft.envs  # noqa: E402,F401
from mjrft.tools.gaits import make_gait, tripod_angles  # noqa: E402


def _run(phase: float, steps: int = 60):
    env = gymnasium.make("mjrft/HexapodSand-v0", medium="poppy_cp", max_episode_steps=1000)
    u = env.unwrapped
    m, d = u.model, u.data
    gait = make_gait(f"tripod:phase={phase}", u)
    obs, _ = env.reset(seed=0)
    q = tripod_angles(u, 0.0, 2.0, phase=phase)
    d.qpos[u.task.hip_qadr] = q
    u.target[:] = q
    d.ctrl[:] = q
    mujoco.mj_forward(m, d)
    obs = u._get_obs()
    for _ in range(steps):
        obs, _, terminated, _, _ = env.step(gait.predict(obs)[0])
        assert not terminated
    w, x, y, z = d.qpos[3:7]
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    env.close()
    return d.qpos[0], d.qpos[1], yaw, roll


def test_tripod_start_is_mirror_symmetric():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        xa, ya, yawa, rolla = _run(0.0)
        xb, yb, yawb, rollb = _run(0.5)
    assert xa > 0.03 and xb > 0.03  # both walk forward
    assert xa == pytest.approx(xb, abs=1e-3)
    assert ya == pytest.approx(-yb, abs=1e-3)
    assert np.degrees(yawa) == pytest.approx(-np.degrees(yawb), abs=1.0)
    assert np.degrees(rolla) == pytest.approx(-np.degrees(rollb), abs=1.0)
