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

How they were chosen (``mjrft bench``, :mod:`mjrft.tradeoff`; the committed run is
``benchmarks/results/trade_study.md``, 2 shared cores). Cost is the wall time per simulated second
relative to the bare MuJoCo model (robots: their rigid-ground twin); errors are against the converged
reference (1/4 of the model's resolution, 0.5 ms, the medium's own fit):

========  =====  ======  ==========  =====================================================================
preset    scale  law     dt x skip   measured (hexapod tripod 2 s / humanoid on one foot 2.5 s)
========  =====  ======  ==========  =====================================================================
fast      4      rft     1 ms x 10   cost 1.83x / 0.96x (default 2.88x / 2.48x); RMS force error 17.0 % /
                                     0.93 %, peak 6.2 % / 0.4 %, final position 18.8 / 2.9 mm
default   1      rft     1 ms x 10   cost 2.88x / 2.48x; RMS force 6.9 % / 0.84 %, peak 0.03 % / 0.2 %,
                                     final position 6.0 / 0.08 mm
accurate  0.5    rft     0.5 ms x 20 cost 14.2x / 20.7x; RMS force 0.41 % / 0.03 %, peak 0.07 % / 0.0 %,
                                     final position 0.37 / 0.02 mm
========  =====  ======  ==========  =====================================================================

The rules (:func:`mjrft.tradeoff.recommend_presets`, worst case over the four scenarios, candidates
with the ``rft`` law, a 10 ms control period and no stability warning): *fast* is the cheapest with RMS
force error <= 20 % and peak force error <= 10 %; *accurate* the cheapest non-reference configuration
with RMS and peak force errors <= 1 % and final position error <= 1 mm. What the study showed:

* the timestep dominates the robots' error: at the model's resolution going from 1 ms to 0.5 ms cuts the
  hexapod's RMS force error from 6.9 % to 1.25 %, while refining the elements 4-fold at 1 ms leaves it
  at 6.9 %;
* 2 ms steps are cheap (hexapod 1.43x) but exceed the explicit stability limit of the granular stiffness
  (``TerrainStabilityWarning`` on the hexapod and the humanoid) and give 41 % RMS force error on the
  hexapod, so no preset uses them;
* Li's fit of the medium (``rft``) costs no more than the cheaper-looking laws: ``depth_only`` saves
  about 10 % of the cost for 25 % RMS force error, ``rft3d`` costs 15-90 % more;
* flat feet need few elements: a fully buried flat face is integrated exactly by one element at its
  centroid (stress is linear in depth), so the humanoid at 8 cm (76 elements) is within 1 % of the
  reference; curved C-legs need the model's 5 mm for peak forces.

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
