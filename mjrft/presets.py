"""Speed/accuracy presets for the environments: ``"fast"``, ``"default"`` and ``"accurate"``.

>>> env = gymnasium.make("mjrft/HexapodSand-v0", preset="fast")
>>> env = gymnasium.make("mjrft/HexapodSand-v0", preset="accurate", law="rft3d")   # explicit kwargs win

Each preset sets:

* ``resolution_scale``: the element size as a multiple of the model's own resolution (its MJCF
  ``<custom>`` ``mjrft:resolution``: hexapod 5 mm, humanoid 2 cm, biped 1 cm), so one preset fits robots
  of every size;
* ``law``: the force law (``rft``, Li 2013 with the medium's own fit, in all three);
* ``timestep`` (s) and ``frame_skip``: the physics step and the steps per env step. All three presets
  keep the control period ``timestep x frame_skip`` at 10 ms, so a policy sees the same task under
  every preset.

How they were chosen (``mjrft bench`` / ``python benchmarks/trade_study.py``, :mod:`mjrft.tradeoff`; the
committed run is ``benchmarks/results/trade_study.md``, 2 cores shared with other jobs). Cost is the wall
time per simulated second relative to the bare MuJoCo model (robots: their rigid-ground twin with the
same controller); errors are against the reference (1/4 of the model's resolution, 0.5 ms, the medium's
own fit), RMS and peak of the net granular force, final position of the torso / pelvis:

========  =====  ======  ===========  ==================================================================
preset    scale  law     dt x skip    measured: hexapod tripod 2 s | humanoid on one foot 2.5 s
========  =====  ======  ===========  ==================================================================
fast      2      rft     1 ms x 10    1.82x, RMS 8.3 %, peak 0.7 %, 7.0 mm | 1.24x, 0.88 %, 0.23 %, 0.6 mm
default   1      rft     1 ms x 10    3.23x, RMS 7.9 %, peak 1.1 %, 2.6 mm | 2.09x, 0.84 %, 0.19 %, 0.1 mm
accurate  0.5    rft     0.5 ms x 20  13.9x, RMS 11.4 %, peak 2.4 %, 10.7 mm | 10.6x, 0.02 %, 0.00 %, 0.02 mm
========  =====  ======  ===========  ==================================================================

(Rigs, same order: plate 3.51x / 4.94x / 28.2x, C-leg 19.5x / 47.4x / 240x against a bare rig of a few
microseconds per step, force errors <= 0.25 %; ``accurate`` is their reference.)

The rules (:func:`mjrft.tradeoff.recommend_presets`; candidates use ``rft``, a 10 ms control period and
warn no more than the default; cost is the geometric mean over the four scenarios, errors the worst case):
*fast* is the cheapest with RMS force error <= 20 % and peak <= 10 % (4x coarser fails on the hexapod:
21 % RMS, 28 mm); *accurate* the cheapest non-reference configuration with RMS and peak force errors
<= 1 % and <= 1/4 of the default's, and final position <= 1 mm, judged on the scenarios whose reference is
converged. The hexapod's is not: its two finest resolutions differ by 11 % RMS force and 9.8 mm, because
the box-chain C-legs count their internal end faces at resolutions >= 2.5 mm and drop them only below
(leg area 18.32 cm^2 at 2.5-20 mm, 17.74 at 1.25 mm, 17.21 at 0.625 mm), so its errors against the 1.25 mm
reference (7-11 % RMS force and 1-11 mm for every configuration at 5 mm or finer) measure that as much as
the timestep.
With the resolution fixed, halving the timestep does converge: at 5 mm the hexapod's final position is
15.7 mm (1 ms) and 4.6 mm (0.5 ms) from a 0.25 ms run. What else the study showed:

* 2 ms steps are cheap (hexapod 1.28x, humanoid 1.10x) but give 32 % RMS force error and 25 mm on the
  hexapod and stability warnings on the humanoid, so no preset uses them;
* Li's fit of the medium (``rft``) is the reference law and costs no more than the others: ``depth_only``
  is 0.9-1.6x its cost with 22-107 % RMS force error, ``rft_generic`` (Li's scaling routine) 0.8-1.2x
  with 1-45 %, ``rft3d`` 1.8-2.3x with 2-93 %;
* flat feet need few elements (a fully buried flat face is integrated exactly by one element at its
  centroid: stress is linear in depth): the humanoid at 8 cm (76 elements) is within 0.94 % RMS force;
* frame skip only changes the per-call overhead (humanoid 1 ms x 1: 3.19x, x 10: 2.09x) and the control
  signal.

The biped is not one of the study's scenarios; its presets use the same scales (its round feet are
curved, so ``fast`` gives it coarser feet than the study tested).
"""

from __future__ import annotations

import mujoco

from .coupler import CUSTOM_PREFIX, DEFAULTS
from .errors import unknown

PRESETS: dict[str, dict] = {
    "fast": {"resolution_scale": 2.0, "law": "rft", "timestep": 0.001, "frame_skip": 10},
    "default": {"resolution_scale": 1.0, "law": "rft", "timestep": 0.001, "frame_skip": 10},
    "accurate": {"resolution_scale": 0.5, "law": "rft", "timestep": 0.0005, "frame_skip": 20},
}


def get_preset(name: str) -> dict:
    """A copy of the preset called ``name``; an unknown name raises an error listing the valid ones."""
    if isinstance(name, str) and name in PRESETS:
        return dict(PRESETS[name])
    raise unknown("preset", name, PRESETS)


def model_resolution(model: mujoco.MjModel) -> float:
    """The model's own element size: its ``<custom>`` ``mjrft:resolution``, else the coupler default."""
    i = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, CUSTOM_PREFIX + "resolution")
    if i < 0:
        return float(DEFAULTS["resolution"])
    return float(model.numeric_data[model.numeric_adr[i]])


def resolve(preset: str | None, *, law=None, resolution=None, timestep=None, frame_skip=None) -> dict:
    """Fill the keyword arguments left as None from ``preset`` (None: nothing filled); explicit values win.

    Returns ``law``, ``resolution`` (m or None), ``resolution_scale`` (applied only when ``resolution``
    is None), ``timestep`` (s or None: the model's own) and ``frame_skip`` (None: the caller's default).
    """
    p = get_preset(preset) if preset is not None else {}
    return {
        "law": law if law is not None else p.get("law"),
        "resolution": resolution,
        "resolution_scale": p.get("resolution_scale", 1.0) if resolution is None else 1.0,
        "timestep": timestep if timestep is not None else p.get("timestep"),
        "frame_skip": frame_skip if frame_skip is not None else p.get("frame_skip"),
    }


__all__ = ["PRESETS", "get_preset", "model_resolution", "resolve"]
