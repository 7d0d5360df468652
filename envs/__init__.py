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
#: gymnasium's MuJoCo robots on sand: mjrft id -> gymnasium id (:mod:`mjrft.envs.wrapper`)
GYM_SAND_IDS = {
    "mjrft/AntSand-v5": "Ant-v5",
    "mjrft/HalfCheetahSand-v5": "HalfCheetah-v5",
    "mjrft/HopperSand-v5": "Hopper-v5",
    "mjrft/Walker2dSand-v5": "Walker2d-v5",
    "mjrft/GymHumanoidSand-v5": "Humanoid-v5",
}
#: ``vector_entry_point`` of each id (``gymnasium.make_vec(id, num_envs)``): a batched ``GranularVectorEnv``
VECTOR_ENTRY_POINTS = {env_id: "mjrft.envs.vector:" + env_id.split("/")[1].split("-")[0] + "Vector"
                       for env_id in ENV_IDS}

__all__ = ["ENV_IDS", "GYM_SAND_IDS", "GranularWrapper", "VECTOR_ENTRY_POINTS", "make_vector", "register_envs"]


def __getattr__(name):
    if name == "GranularWrapper":  # imported on first use (it imports gymnasium's MuJoCo envs)
        from .wrapper import GranularWrapper

        return GranularWrapper
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def make_vector(env_id: str, num_envs: int = 1, **kwargs):
    """``num_envs`` copies of ``env_id`` stepped as one batch: a :class:`mjrft.envs.vector.GranularVectorEnv`
    (gymnasium vector API; keyword arguments: ``max_episode_steps``, ``autoreset_mode``, ``parallel`` and the
    environment's own). ``gymnasium.make_vec(env_id, num_envs)`` builds the same."""
    from .vector import GranularVectorEnv

    return GranularVectorEnv(env_id, num_envs, **kwargs)


def register_envs() -> list[str]:
    """Register the mjrft environments and the sand variants of gymnasium's robots with gymnasium (ids already
    registered are left alone); returns the registered ids."""
    try:
        import gymnasium
    except ImportError:  # gymnasium is optional for mjrft
        return []
    for env_id, entry_point in ENV_IDS.items():
        if env_id not in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point=entry_point, max_episode_steps=MAX_EPISODE_STEPS,
                               vector_entry_point=VECTOR_ENTRY_POINTS[env_id])
    for env_id, gym_id in GYM_SAND_IDS.items():
        if env_id not in gymnasium.registry and gym_id in gymnasium.registry:
            gymnasium.register(id=env_id, entry_point="mjrft.envs.wrapper:make_sand_env", kwargs={"gym_id": gym_id},
                               max_episode_steps=gymnasium.registry[gym_id].max_episode_steps)
    return list(ENV_IDS) + [i for i in GYM_SAND_IDS if i in gymnasium.registry]


register_envs()
