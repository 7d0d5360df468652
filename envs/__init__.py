"""Gymnasium environments of mjrft (installed as ``mjrft.envs``).

Importing this module registers (idempotently, see :func:`register_envs`):

=========================  ===========================================  ==================
id                         entry point                                  max_episode_steps
=========================  ===========================================  ==================
``mjrft/HexapodSand-v0``   ``mjrft.envs.hexapod:HexapodSand``           1000 (10 s)
``mjrft/HexapodRigid-v0``  ``mjrft.envs.hexapod:HexapodRigid``          1000
``mjrft/BipedSand-v0``     ``mjrft.envs.biped:BipedSand``               1000
``mjrft/BipedRigid-v0``    ``mjrft.envs.biped:BipedRigid``              1000
``mjrft/HumanoidSand-v0``  ``mjrft.envs.humanoid:HumanoidSand``         1000
``mjrft/HumanoidRigid-v0`` ``mjrft.envs.humanoid:HumanoidRigid``        1000
=========================  ===========================================  ==================

>>> import gymnasium
>>> env = gymnasium.make("mjrft.envs:mjrft/HexapodSand-v0", max_episode_steps=200, medium="poppy_lp")

Headless rendering (``render_mode="rgb_array"``) needs ``MUJOCO_GL=egl`` or ``MUJOCO_GL=osmesa``.
"""

from __future__ import annotations

ENV_IDS = {
    "mjrft/HexapodSand-v0": "mjrft.envs.hexapod:HexapodSand",
    "mjrft/HexapodRigid-v0": "mjrft.envs.hexapod:HexapodRigid",
    "mjrft/BipedSand-v0": "mjrft.envs.biped:BipedSand",
    "mjrft/BipedRigid-v0": "mjrft.envs.biped:BipedRigid",
    "mjrft/HumanoidSand-v0": "mjrft.envs.humanoid:HumanoidSand",
    "mjrft/HumanoidRigid-v0": "mjrft.envs.humanoid:HumanoidRigid",
}
MAX_EPISODE_STEPS = 1000

__all__ = ["ENV_IDS", "register_envs"]


def register_envs() -> list[str]:
    """Register the mjrft environments with gymnasium (ids already registered are left alone)."""
    try:
        import gymnasium
    except ImportError:  # gymnasium is optional for mjrft
        return []
    for env_id, entry_point in ENV_IDS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=entry_point, max_episode_steps=MAX_EPISODE_STEPS)
    return list(ENV_IDS)


register_envs()
