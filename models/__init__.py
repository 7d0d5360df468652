"""Robot and scene MJCF models for mjrft (installed as ``mjrft.models``).

``model_path(name)`` gives the path of a committed default model (regenerate
them with ``python -m mjrft.models.generate``); the parametric generators
``hexapod_xml/hexapod_model``, ``biped_xml/biped_model`` and
``humanoid_xml/humanoid_model``, the rigs' ``plate_rig_xml/leg_rig_xml`` and the shoal scene's
``hexapod_shoal_xml/hexapod_shoal_model`` and SGRFT's propeller-leg robot
``propeller_robot_xml/propeller_robot_model`` and DynaRoACH with its swing-and-lift legs
``dynaroach_xml/dynaroach_model`` are re-exported here (imported lazily).
"""

from __future__ import annotations

import sys as _sys

if getattr(_sys.modules.get("mjrft"), "__file__", None) is None:  # a clone folder named mjrft, found first
    raise ImportError(f"{__name__} was imported from a folder named 'mjrft' that holds the mjrft repository, not from "
                      "the installed package: run the script from another folder (or inside the repository)")

import os

_DIR = os.path.dirname(os.path.abspath(__file__))

#: Committed default models (name -> file), see ``generate.py``.
MODEL_NAMES = (
    "hexapod",
    "hexapod_rigid",
    "hexapod_small",
    "hexapod_small_rigid",
    "biped",
    "biped_wedge",
    "biped_rigid",
    "humanoid",
    "humanoid_cutout",
    "humanoid_rigid",
    "plate_rig",
    "leg_rig",
    "hexapod_shoal",
)

_LAZY = {
    "hexapod_xml": "hexapod", "hexapod_model": "hexapod",
    "biped_xml": "biped", "biped_model": "biped",
    "humanoid_xml": "humanoid", "humanoid_model": "humanoid",
    "plate_rig_xml": "rigs", "leg_rig_xml": "rigs",
    "hexapod_shoal_xml": "shoal", "hexapod_shoal_model": "shoal",
    "propeller_robot_xml": "propeller_robot", "propeller_robot_model": "propeller_robot",
    "dynaroach_xml": "dynaroach", "dynaroach_model": "dynaroach",
}

__all__ = ["MODEL_NAMES", "model_path", *_LAZY]


def model_path(name: str) -> str:
    """Absolute path of the committed model ``name`` (with or without ``.xml``)."""
    key = name[:-4] if isinstance(name, str) and name.endswith(".xml") else name
    if key not in MODEL_NAMES:
        raise ValueError(f"unknown model {name!r}; valid names: {', '.join(MODEL_NAMES)}")
    return os.path.join(_DIR, f"{key}.xml")


def __getattr__(attr: str):
    if attr in _LAZY:
        import importlib

        module = importlib.import_module(f".{_LAZY[attr]}", __name__)
        return getattr(module, attr)
    raise AttributeError(f"module {__name__!r} has no attribute {attr!r}")
