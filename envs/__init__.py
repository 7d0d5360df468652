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
``mjrft/HexapodShoal-v0``  ``mjrft.envs.hexapod:HexapodShoal``          1000
=========================  ===========================================  ==================

>>> import gymnasium
>>> env = gymnasium.make("mjrft.envs:mjrft/HexapodSand-v0", max_episode_steps=200, medium="poppy_lp")

Headless rendering (``render_mode="rgb_array"``) needs ``MUJOCO_GL=egl`` or ``MUJOCO_GL=osmesa``.
"""

from __future__ import annotations

import sys as _sys

if getattr(_sys.modules.get("mjrft"), "__file__", None) is None:  # a clone folder named mjrft, found first
    raise ImportError(f"{__name__} was imported from a folder named 'mjrft' that holds the mjrft repository, not from "
                      "the installed package: run the script from another folder (or inside the repository)")

ENV_IDS = {
    "mjrft/HexapodSand-v0": "mjrft.envs.hexapod:HexapodSand",
    "mjrft/HexapodRigid-v0": "mjrft.envs.hexapod:HexapodRigid",
    "mjrft/BipedSand-v0": "mjrft.envs.biped:BipedSand",
    "mjrft/BipedRigid-v0": "mjrft.envs.biped:BipedRigid",
    "mjrft/HumanoidSand-v0": "mjrft.envs.humanoid:HumanoidSand",
    "mjrft/HumanoidRigid-v0": "mjrft.envs.humanoid:HumanoidRigid",
    "mjrft/HexapodShoal-v0": "mjrft.envs.hexapod:HexapodShoal",
}
MAX_EPISODE_STEPS = 1000
#: ``vector_entry_point`` of each id (``gymnasium.make_vec(id, num_envs)``): a batched ``GranularVectorEnv``
VECTOR_ENTRY_POINTS = {env_id: "mjrft.envs.vector:" + env_id.split("/")[1].split("-")[0] + "Vector"
                       for env_id in ENV_IDS}

__all__ = ["ENV_IDS", "VECTOR_ENTRY_POINTS", "make_vector", "register_envs"]


def make_vector(env_id: str, num_envs: int = 1, **kwargs):
    """``num_envs`` copies of ``env_id`` stepped as one batch: a :class:`mjrft.envs.vector.GranularVectorEnv`
    (gymnasium vector API; keyword arguments: ``max_episode_steps``, ``autoreset_mode``, ``parallel`` and the
    environment's own). ``gymnasium.make_vec(env_id, num_envs)`` builds the same."""
    from .vector import GranularVectorEnv

    return GranularVectorEnv(env_id, num_envs, **kwargs)


def register_envs() -> list[str]:
    """Register the mjrft environments with gymnasium (ids already registered are left alone)."""
    try:
        import gymnasium
    except ImportError:  # gymnasium is optional for mjrft
        return []
    for env_id, entry_point in ENV_IDS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=entry_point, max_episode_steps=MAX_EPISODE_STEPS,
                               vector_entry_point=VECTOR_ENTRY_POINTS[env_id])
    return list(ENV_IDS)


register_envs()
