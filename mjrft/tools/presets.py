"""Speed/accuracy presets for the environments: ``"fast"``, ``"default"`` and ``"accurate"``.

>>> env = gymnasium.make("mjrft/HexapodSand-v0", preset="fast")
>>> env = gymnasium.make("mjrft/HexapodSand-v0", preset="accurate", law="rft3d")   # explicit kwargs win

Each preset sets:

* ``resolution_scale``: the element size as a multiple of the model's own resolution (its MJCF
  ``<custom>`` ``mjrft:resolution``: hexapod 5 mm, humanoid 2 cm, biped 2 cm; ``"auto"``'s size for a model
  without one), so one preset fits robots of every size (:class:`mjrft.GranularTerrain`'s ``resolution_scale``);
* ``law``: the force law (``rft``, Li 2013 with the medium's own fit, in all three);
* ``timestep`` (s) and ``frame_skip``: the physics step and the steps per env step. All three presets
  keep the control period ``timestep x frame_skip`` at 10 ms, so a policy sees the same task under
  every preset.

How they were chosen (``mjrft bench`` / ``python benchmarks/trade_study.py``, :mod:`mjrft.tools.tradeoff`; the
committed run is ``benchmarks/results/trade_study.md``). Cost is the wall time per simulated second
relative to the bare MuJoCo model (robots: their rigid-ground twin with the same controller); errors are
against the reference (1/4 of the model's resolution, 0.5 ms, the medium's own fit), RMS and peak of the
net granular force, final position of the torso / pelvis:

========  =====  ======  ===========  ==================================================================
preset    scale  law     dt x skip    measured: planar hexapod tripod 2 s | humanoid on one foot 2.5 s
========  =====  ======  ===========  ==================================================================
fast      4      rft     1 ms x 10    0.94x, RMS 11.4 %, peak 3.2 %, 12.2 mm | 0.92x, 0.94 %, 0.41 %, 2.7 mm
default   1      rft     1 ms x 10    1.76x, RMS 7.1 %, peak 2.9 %, 2.7 mm | 2.07x, 0.84 %, 0.20 %, 0.08 mm
accurate  0.5    rft     0.5 ms x 20  9.93x, RMS 0.68 %, peak 0.11 %, 0.36 mm | 11.2x, 0.03 %, 0.00 %, 0.02 mm
========  =====  ======  ===========  ==================================================================

(Rigs, same order: plate 3.62x / 6.77x / 23.6x, C-leg 4.50x / 40.6x / 193x against a bare rig of a few
microseconds per step, force errors <= 0.74 %; ``accurate`` is their reference.)

The rules (:func:`mjrft.tools.tradeoff.recommend_presets`; candidates use ``rft``, a 10 ms control period and
warn no more than the default; cost is the geometric mean over the scenarios that choose presets, errors
the worst case): *fast* is the cheapest with RMS force error <= 20 % and peak <= 10 % (4x coarser: worst
11.4 % RMS, on the hexapod); *accurate* the cheapest non-reference configuration with RMS and peak force
errors <= 1 % and <= 1/4 of the default's, and final position <= 1 mm, judged on the scenarios whose
reference is converged (all four: the planar hexapod's two finest resolutions differ by 0.67 % RMS force
and 0.43 mm). The small hexapod at 10 Hz is reported but takes no part (its 1 ms default is already 22 %
from its 0.5 ms reference: fast gaits need a finer timestep). The timestep, not the elements, limits the
robots. What else the study showed:

* 2 ms steps are cheap (hexapod 0.77x, humanoid 0.97x) but give 31 % RMS force error on the hexapod and
  stability warnings on the humanoid, so no preset uses them;
* Li's fit of the medium (``rft``) is the reference law and costs no more than the others: ``depth_only``
  is 1.2-2x its cost with 26-72 % RMS force error, ``rft_generic`` (Li's scaling routine) 0.9-1.2x
  with 1.2-13.5 %, ``rft3d`` 1.7-4.2x with 2-37 %;
* flat feet need few elements (a fully buried flat face is integrated exactly by one element at its
  centroid: stress is linear in depth): the humanoid at 8 cm (76 elements) is within 0.94 % RMS force;
* frame skip only changes the per-call overhead and the control signal.

The biped is not one of the study's scenarios; its presets use the same scales.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mjrft.errors import check_positive, unknown
from mjrft.laws import law_id
from mjrft.media import Medium, get_medium

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
            frame_skip=None, own_step: tuple[float, int] | None = None) -> EnvSettings:
    """The :class:`EnvSettings` of keyword arguments where those left as None come from ``preset`` (None: nothing
    filled; ``frame_skip`` then defaults to :data:`FRAME_SKIP`); explicit values win. ``own_step``: the robot's own
    ``(timestep, frame_skip)``, used when neither ``preset``, ``timestep`` nor ``frame_skip`` is given. Each value
    is checked here, naming the bad value and the valid choices (rigid environments too, where medium and law go
    unused).

    The preset's ``resolution_scale`` applies only when ``resolution`` is None.
    """
    if own_step is not None and preset is None and timestep is None and frame_skip is None:
        timestep, frame_skip = own_step
    p = get_preset(preset) if preset is not None else {}
    law = law if law is not None else p.get("law")
    timestep = timestep if timestep is not None else p.get("timestep")
    frame_skip = frame_skip if frame_skip is not None else p.get("frame_skip", FRAME_SKIP)
    if law is not None:
        law_id(law)
    if resolution is not None:
        resolution = check_positive("resolution", resolution)
    scale = p.get("resolution_scale", 1.0) if resolution is None else 1.0
    if timestep is not None:
        timestep = check_positive("timestep", timestep)
    return EnvSettings(medium=None if medium is None else get_medium(medium), law=law, resolution=resolution,
                       resolution_scale=scale, timestep=timestep, frame_skip=check_frame_skip(frame_skip))


__all__ = ["FRAME_SKIP", "PRESETS", "EnvSettings", "check_frame_skip", "get_preset", "resolve"]
