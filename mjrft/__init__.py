"""mjrft: granular terrain (resistive force theory) for MuJoCo.

>>> import mujoco, mjrft
>>> terrain = mjrft.GranularTerrain(model, medium="poppy_cp", law="rft", bodies=["foot"])
>>> terrain.step(data)

Two layers. The physics core: the records every path shares (:mod:`mjrft.types`: :class:`TerrainModel`,
what a terrain is, and :class:`TerrainState`, what it remembers; the parameter vector's layout in
:mod:`mjrft.params`), built by :mod:`mjrft.build` from what they are made of (:mod:`mjrft.settings`,
:mod:`mjrft.selection`, :mod:`mjrft.floor`, :mod:`mjrft.regions`, :mod:`mjrft.elements`); :mod:`mjrft.coupler`
(:class:`GranularTerrain`, the only code that reads ``mjData``) steps them with :mod:`mjrft.kernel` (the compiled
per-step kernel, :mod:`mjrft.surface` its surface and regions), :mod:`mjrft.stepping` (the fused stepping loop),
:mod:`mjrft.implicit_step`, :mod:`mjrft.mujoco_c` (MuJoCo's C functions), :mod:`mjrft.stability` and
:mod:`mjrft.watch` (the checks); :mod:`mjrft.batch` (many terrains stepped in one call), :mod:`mjrft.media`,
:mod:`mjrft.laws`, :mod:`mjrft.geometry` and :mod:`mjrft.errors`. On top of it
:mod:`mjrft.tools` (the command line, rigs, gaits, presets, the trade study, calibration, rerun logging,
output paths and the validation against the papers), :mod:`mjrft.models` (the robots' MJCF),
:mod:`mjrft.envs` (gymnasium environments) and :mod:`mjrft.train`. The core imports nothing from
:mod:`mjrft.tools`, :mod:`mjrft.envs` or :mod:`mjrft.train`.

This package imports the core and :mod:`mjrft.models`; ``mjrft.tools`` is imported on first access of the
attribute. When gymnasium is installed it also imports :mod:`mjrft.envs`, which registers the environments'
ids, so ``gymnasium.make("mjrft/HexapodSand-v0")`` works after ``import mjrft``.
"""

from . import _jit_cache  # noqa: F401  (must precede every compiled module)
from .coupler import GranularTerrain
from .regions import Region
from .types import TerrainModel, TerrainState
from .errors import (MjrftError, NonFiniteError, SandContactWarning, TerrainStabilityWarning, UnknownNameError,
                     ValidityRangeWarning)
from .media import MEDIA, Medium, calibrate, fluidized, generic, get_medium, medium_3d
from . import laws
from . import models

try:  # gymnasium environments register themselves ("mjrft/HexapodSand-v0", ...) when gymnasium is installed
    import gymnasium as _gymnasium  # noqa: F401
except ImportError:  # pragma: no cover - the envs extra is optional
    pass
else:
    from . import envs  # noqa: F401


def __getattr__(name):
    if name == "tools":  # imported on first use: the core does not import it
        import importlib

        return importlib.import_module(f"{__name__}.tools")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__version__ = "0.1.0"

__all__ = ["GranularTerrain", "MEDIA", "Medium", "MjrftError", "NonFiniteError", "Region", "SandContactWarning",
           "TerrainModel", "TerrainStabilityWarning", "TerrainState", "UnknownNameError", "ValidityRangeWarning",
           "calibrate", "fluidized", "generic", "get_medium", "laws", "medium_3d", "models", "tools"]
