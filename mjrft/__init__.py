"""mjrft: granular terrain (resistive force theory) for MuJoCo.

>>> import mujoco, mjrft
>>> terrain = mjrft.GranularTerrain(model, medium="poppy_cp", law="rft", bodies=["foot"])
>>> terrain.step(data)

Two layers. The physics core: :mod:`mjrft.coupler` (:class:`GranularTerrain`, the only code that reads
``mjData``), :mod:`mjrft.kernel` (the compiled per-step kernel), :mod:`mjrft.batch` (many terrains stepped in
one call), :mod:`mjrft.media`, :mod:`mjrft.laws`, :mod:`mjrft.geometry` and :mod:`mjrft.errors`. On top of it
:mod:`mjrft.tools` (the command line, rigs, gaits, presets, the trade study, calibration, rerun logging,
output paths and the validation against the papers), :mod:`mjrft.models` (the robots' MJCF),
:mod:`mjrft.envs` (gymnasium environments) and :mod:`mjrft.train`. The core imports nothing from the
layers above it.

A tool's former path ``mjrft.<tool>`` (``mjrft.gaits``, ``mjrft.validation.cases.li2013``, ...) imports the
module at ``mjrft.tools.<tool>``, the same object, with a DeprecationWarning naming the new path
(:class:`_MovedToTools`); ``python -m`` and pickles that name a former path work the same way.
"""

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
import warnings

from . import _jit_cache  # noqa: F401  (must precede every compiled module)
from .coupler import GranularTerrain, Region
from .errors import (MjrftError, NonFiniteError, SandContactWarning, TerrainStabilityWarning, UnknownNameError,
                     ValidityRangeWarning)
from .media import MEDIA, Medium, calibrate, generic, get_medium, medium_3d
from . import laws
from . import models
from . import tools


class _MovedToTools(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Import hook for the former paths of the tools: ``mjrft.<tool>[.<sub>]`` for each module in
    ``mjrft.tools.__all__`` resolves to ``mjrft.tools.<tool>[.<sub>]``.

    The module is imported under its new name and the same object is bound to the former one (so
    ``mjrft.gaits.make_gait is mjrft.tools.gaits.make_gait``, and a pickle naming ``mjrft.gaits`` loads);
    each former name warns once, with a DeprecationWarning naming the new path. ``python -m mjrft.cli``
    runs the code of ``mjrft.tools.cli`` (:meth:`get_code`).
    """

    def __init__(self, package: str, moved):
        self.package = package
        self.moved = frozenset(moved)

    def new_name(self, fullname: str) -> str | None:
        """The new dotted name of a former path, or None for any other name."""
        parts = fullname.split(".")
        if len(parts) < 2 or parts[0] != self.package or parts[1] not in self.moved:
            return None
        return ".".join([self.package, "tools", *parts[1:]])

    def find_spec(self, fullname, path=None, target=None):
        new = self.new_name(fullname)
        if new is None:
            return None
        spec = importlib.util.find_spec(new)
        if spec is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, self, origin=spec.origin,
                                              is_package=spec.submodule_search_locations is not None)

    def create_module(self, spec):
        new = self.new_name(spec.name)
        self._warn(spec.name, new)
        module = importlib.import_module(new)
        spec.loader_state = module.__spec__
        return module

    def exec_module(self, module):
        # the import system has just set the module's __spec__ to the former name's; the module keeps its own
        module.__spec__ = module.__spec__.loader_state

    def get_code(self, fullname):
        new = self.new_name(fullname)
        self._warn(fullname, new)
        return importlib.util.find_spec(new).loader.get_code(new)

    @staticmethod
    def _warn(old: str, new: str) -> None:
        warnings.warn(f"{old} is now {new}; import {new} instead", DeprecationWarning, stacklevel=3)


if not any(isinstance(f, _MovedToTools) for f in sys.meta_path):
    sys.meta_path.insert(0, _MovedToTools(__name__, tools.__all__))

try:  # gymnasium environments register themselves ("mjrft/HexapodSand-v0", ...) when gymnasium is installed
    import gymnasium as _gymnasium  # noqa: F401
except ImportError:  # pragma: no cover - the envs extra is optional
    pass
else:
    from . import envs  # noqa: F401

__version__ = "0.1.0"

__all__ = ["GranularTerrain", "MEDIA", "Medium", "MjrftError", "NonFiniteError", "Region", "SandContactWarning",
           "TerrainStabilityWarning", "UnknownNameError", "ValidityRangeWarning", "calibrate", "generic", "get_medium",
           "laws", "medium_3d", "models", "tools"]
