"""Speed/accuracy presets for the environments: ``"fast"``, ``"default"`` and ``"accurate"``.

>>> env = gymnasium.make("mjrft/HexapodSand-v0", preset="fast")
>>> env = gymnasium.make("mjrft/HexapodSand-v0", preset="accurate", law="rft3d")   # explicit kwargs win

Each preset sets:

* ``resolution_scale``: the element size as a multiple of the model's own resolution (its MJCF
  ``<custom>`` ``mjrft:resolution``: hexapod 5 mm, humanoid 2 cm, biped 2 cm; ``"auto"``'s size for a model
  without one), so one preset fits robots of every size (:class:`mjrft.GranularTerrain`'s ``resolution_scale``);
* ``law``: the force law (``rft``, Li 2013 with the medium's own fit, in all three);
* ``timestep`` (s) and ``frame_skip``: the physics step and the steps per env step, always a 10 ms control period,
  so a policy sees the same task under every preset. An environment steps each preset at its robot's own measured
  step (``preset_steps`` of :func:`resolve`; :class:`mjrft.envs.base.GranularMujocoEnv`'s ``fast_step`` and
  ``accurate_step``): ``default`` at the robot's own step (the one it takes without a preset); ``fast`` at the own
  step too, halved while the preset's coarse elements warn more than the default (no preset is less stable than
  the default: the biped's 1 ms); ``accurate`` at the largest step within the 2 % gait budget of ``python
  benchmarks/env_timestep.py`` (gait speed and sinkage against a 0.05 ms reference), no coarser than the robot's
  own step (the finest step that study measures where none is within budget). The values in :data:`PRESETS` are
  the step of a scene without its own (the trade study's scenarios).

How the element size and the law were chosen: by the trade study (``mjrft bench`` / ``python
benchmarks/trade_study.py``, :mod:`mjrft.tools.tradeoff`), which measures the cost (wall time per simulated second
relative to the rigid-ground twin with the same controller) and the error (RMS and peak of the net granular force,
final torso / pelvis position, against the reference: 1/4 of the model's resolution, 0.5 ms, the medium's own fit)
of configurations around the default. Its committed run is ``benchmarks/results/trade_study.md``; each
environment's presets are measured by ``python benchmarks/env_presets.py`` (``benchmarks/results/env_presets.txt``);
docs/speed-accuracy.md is their one page.

========  =====  ======  ====================  ===============================================
preset    scale  law     dt x skip (a scene)   dt x skip (an environment)
========  =====  ======  ====================  ===============================================
fast      4      rft     1 ms x 10             the robot's own step, halved until stable
default   1      rft     1 ms x 10             the robot's own step
accurate  0.5    rft     0.5 ms x 20           the largest step within the 2 % gait budget
========  =====  ======  ====================  ===============================================

The rules (:func:`mjrft.tools.tradeoff.recommend_presets`; candidates use ``rft``, a 10 ms control period and
warn no more than the default; cost is the geometric mean over the scenarios that choose presets, errors
the worst case): *fast* is the cheapest with RMS force error <= 20 % and peak <= 10 %; *accurate* the cheapest
non-reference configuration with RMS and peak force errors <= 1 % and <= 1/4 of the default's, and final
position <= 1 mm, judged on the scenarios whose reference is converged. The small hexapod at 10 Hz is reported
but takes no part (fast gaits need a finer timestep than its 1 ms default).

The biped is not one of the study's scenarios; its presets use the same scales.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mjrft.errors import check_positive, unknown
from mjrft.laws import law_id
from mjrft.media import Medium, get_medium
from mjrft.settings import element_size_scale

PRESETS: dict[str, dict] = {
    "fast": {"resolution_scale": 4.0, "law": "rft", "timestep": 0.001, "frame_skip": 10},
    "default": {"resolution_scale": 1.0, "law": "rft", "timestep": 0.001, "frame_skip": 10},
    "accurate": {"resolution_scale": 0.5, "law": "rft", "timestep": 0.0005, "frame_skip": 20},
}
FRAME_SKIP = 10  # physics steps per env step without a preset or a frame_skip argument


def get_preset(name: str) -> dict:
    """A copy of the preset called ``name``; an unknown name raises an error listing the valid ones."""
    if isinstance(name, str) and name in PRESETS:
        return dict(PRESETS[name])
    raise unknown("preset", name, PRESETS)


@dataclass(frozen=True)
class EnvSettings:
    """An environment's simulation settings, each checked once (:func:`resolve`): ``medium`` and ``law`` (None:
    the model's own), ``resolution`` (m; None: ``resolution_scale`` times the model's own, which
    :class:`mjrft.GranularTerrain` applies), ``timestep`` (s; None: the model's own) and ``frame_skip``."""

    medium: Medium | None
    law: str | None
    resolution: float | None
    resolution_scale: float
    timestep: float | None
    frame_skip: int


def check_frame_skip(frame_skip) -> int:
    """``frame_skip`` as an int; anything but an integer >= 1 raises, naming the value."""
    if isinstance(frame_skip, bool) or not isinstance(frame_skip, (int, np.integer)) or frame_skip < 1:
        raise ValueError(f"frame_skip must be an integer >= 1, got {frame_skip!r}")
    return int(frame_skip)


def resolve(preset: str | None, *, medium=None, law=None, resolution=None, timestep=None,
            frame_skip=None, own_step: tuple[float, int] | None = None,
            preset_steps: dict[str, tuple[float | None, int]] | None = None) -> EnvSettings:
    """The :class:`EnvSettings` of keyword arguments where those left as None come from ``preset`` (None: nothing
    filled; ``frame_skip`` then defaults to :data:`FRAME_SKIP`); explicit values win. ``own_step``: the robot's own
    ``(timestep, frame_skip)``, used when neither ``preset``, ``timestep`` nor ``frame_skip`` is given.
    ``preset_steps``: the robot's own ``(timestep, frame_skip)`` per preset name (a timestep of None: the model's),
    which replaces the preset's generic step. Each value is checked here, naming the bad value and the valid choices
    (rigid environments too, where medium and law go unused).

    The preset's ``resolution_scale`` applies only when ``resolution`` is None
    (:func:`mjrft.settings.element_size_scale`, the rule the terrain's own ``resolution_scale`` follows).
    """
    if own_step is not None and preset is None and timestep is None and frame_skip is None:
        timestep, frame_skip = own_step
    p = get_preset(preset) if preset is not None else {}
    if p and preset_steps is not None and preset in preset_steps:
        p["timestep"], p["frame_skip"] = preset_steps[preset]
    law = law if law is not None else p.get("law")
    timestep = timestep if timestep is not None else p.get("timestep")
    frame_skip = frame_skip if frame_skip is not None else p.get("frame_skip", FRAME_SKIP)
    if law is not None:
        law_id(law)
    if resolution is not None:
        resolution = check_positive("resolution", resolution)
    scale = element_size_scale(resolution, p.get("resolution_scale", 1.0))
    if timestep is not None:
        timestep = check_positive("timestep", timestep)
    return EnvSettings(medium=None if medium is None else get_medium(medium), law=law, resolution=resolution,
                       resolution_scale=scale, timestep=timestep, frame_skip=check_frame_skip(frame_skip))


__all__ = ["FRAME_SKIP", "PRESETS", "EnvSettings", "check_frame_skip", "get_preset", "resolve"]
