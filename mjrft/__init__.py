"""mjrft: granular terrain (resistive force theory) for MuJoCo.

>>> import mujoco, mjrft
>>> terrain = mjrft.GranularTerrain(model, medium="poppy_cp", law="rft", bodies=["foot"])
>>> terrain.step(data)
"""

from . import _jit_cache  # noqa: F401  (must precede every compiled module)
from .coupler import GranularTerrain, Region
from .errors import MjrftError, NonFiniteError, TerrainStabilityWarning, UnknownNameError, ValidityRangeWarning
from .media import MEDIA, Medium, calibrate, generic, get_medium, medium_3d
from . import laws
from . import models

try:  # gymnasium environments register themselves ("mjrft/HexapodSand-v0", ...) when gymnasium is installed
    import gymnasium as _gymnasium  # noqa: F401
except ImportError:  # pragma: no cover - the envs extra is optional
    pass
else:
    from . import envs  # noqa: F401

__version__ = "0.1.0"

__all__ = ["GranularTerrain", "MEDIA", "Medium", "MjrftError", "NonFiniteError", "Region", "TerrainStabilityWarning",
           "UnknownNameError", "ValidityRangeWarning", "calibrate", "generic", "get_medium", "laws", "medium_3d", "models"]
