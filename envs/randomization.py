"""Terrain randomisation: a new terrain drawn at every ``reset()`` of a sand environment (robust gaits).

>>> env = gymnasium.make("mjrft/HexapodSand-v0",
...                      terrain_randomization={"media": ["poppy_cp", "poppy_lp"], "stress_scale": [0.7, 1.3]})
>>> obs, info = env.reset(seed=3)       # the same seed draws the same terrain
>>> info["terrain"]                     # what was drawn (also in every step's info)
{'medium': 'poppy_lp', 'stress_scale': 0.9827857991090988, 'surface_height': 0.0, 'roughness': 0.0, 'strips': ()}

From the command line the option is one JSON value:
``mjrft train ... terrain_randomization='{"media": ["poppy_cp", "poppy_lp"], "stress_scale": [0.7, 1.3]}'``.

Options (the keys of the dict, the fields of :class:`TerrainRandomization`); each is off by default, and an
environment without ``terrain_randomization`` (or with every option off) draws nothing and steps exactly as
before:

======================  =================================================================================
``media``               list of medium names (``mjrft.MEDIA``); each reset draws the bed's medium
                        uniformly from it (its law stays the environment's ``law``), and each strip's.
``stress_scale``        ``[low, high]`` (> 0): a factor drawn uniformly, multiplying every granular stress
                        of the law in every region (:meth:`mjrft.GranularTerrain.set_medium`): the grains'
                        forces scale by it (the water's drag and buoyancy do not). A number: that factor.
                        Stiffer grains lower the stability limit: the terrain's stability check sees the
                        scaled stiffness and its warning names the scale. The RHex-class hexapod's 2 Hz
                        tripod on ``poppy_cp`` (the stiffest Li medium) stays within the limit of its env's
                        0.5 ms step at every scale from 0.5 to 5 (``benchmarks/bench_randomization.py``;
                        the numbers in docs/environments.md).
``surface_height``      ``[low, high]`` (m): the sand surface is raised (+) or lowered (-) by a height drawn
                        uniformly, relative to the model's own surface (z = 0 in the bundled scenes). The
                        robot's start pose does not move: a raised surface starts it buried that deep, a
                        lowered one drops it. A number: that height.
``roughness``           RMS height (m, >= 0) of a smooth random height field added to the surface, new at
                        each reset: Gaussian-correlated, ``<h(r) h(r + d)> = roughness^2 exp(-|d|^2 /
                        correlation_length^2)``, with mean 0 and RMS exactly ``roughness`` over the bed,
                        sampled on the scene's height-field surface and bilinear between samples (the
                        rendered hfield shows it). Needs a height-field sand surface: the hexapod envs add
                        one (model option ``surface_grid``, default :data:`DEFAULT_SURFACE_GRID`); other
                        robots take ``surface_grid=<m>`` as a keyword argument; a gymnasium env on sand
                        (:class:`~mjrft.envs.wrapper.GranularWrapper`) needs an hfield floor.
``correlation_length``  m (> 0, default 0.05; at least two ``surface_grid`` samples).
``strips``              ``[min, max]`` (integers >= 0): the number ``n`` of strip boundaries along x, drawn
                        uniformly; the bed's medium holds for ``x < strip_start + L_1``, then ``n`` strips
                        follow, each ``L_k`` long (the last one reaching the bed's end), each with a medium
                        drawn from ``media`` and the environment's law (:meth:`set_regions`; neighbours
                        blend over the terrain's ``transition``). They replace the scene's own regions. A
                        number: that many. Needs ``media``.
``strip_length``        ``[low, high]`` (m, >= the terrain's transition width): each ``L_k``, uniform
                        (default ``[0.2, 0.5]``).
``strip_start``         x (m) where the strip layout starts (default 0: the robot's start).
======================  =================================================================================

Every sand environment takes the option: mjrft's own and the gymnasium robots on sand (the ``*Sand-v5`` ids,
:class:`~mjrft.envs.wrapper.GranularWrapper`, whose flat floor drawn as the sand moves with ``surface_height``).
The MJX environments (:mod:`mjrft.envs.mjx`) take the same options as their ``randomization`` configuration and
draw them per world in JAX.
Draws come from the environment's ``np_random`` (after the reset noise of the start pose, in the order of
the table), so ``reset(seed=s)`` reproduces the terrain, and a vector environment's sub-environment ``i``
(seed ``s + i``) draws what a single environment seeded ``s + i`` draws. ``info["terrain"]`` (at reset and
in every step's info) holds what the terrain is: ``medium`` (name of the bed's medium), ``stress_scale``,
``surface_height`` (m, the drawn raise), ``roughness`` (m RMS), ``strips`` (tuple of ``(x_min, medium)``).

Bad options raise when the environment is made, naming the option, the value and the valid choices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import mujoco
import numpy as np

from mjrft.coupler import GranularTerrain
from mjrft.regions import Region
from mjrft.errors import check_finite, check_positive, unknown
from mjrft.media import MEDIA, Medium

__all__ = ["DEFAULT_SURFACE_GRID", "TerrainRandomization", "TerrainRandomizer", "rough_field", "upload_surface"]

#: sample spacing (m) of the height-field sand surface the hexapod envs add for ``roughness`` (a quarter of the
#: RHex-class leg's 4.1 cm chord: the bumps a leg meets are resolved, the field stays 201 x 101 on the 2 x 1 m bed)
DEFAULT_SURFACE_GRID = 0.01


def _range(name: str, value, *, positive: bool = False) -> tuple[float, float] | None:
    """``None``, a number ``x`` (-> ``(x, x)``) or ``[low, high]`` with low <= high, checked."""
    if value is None:
        return None
    if isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
        value = (value, value)
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__") or len(value) != 2:
        raise ValueError(f"terrain_randomization {name} must be [low, high] or a number, got {value!r}")
    check = (lambda v: check_positive(f"terrain_randomization {name}", v)) if positive else (
        lambda v: check_finite(f"terrain_randomization {name}", v))
    lo, hi = check(value[0]), check(value[1])
    if lo > hi:
        raise ValueError(f"terrain_randomization {name} must be [low, high] with low <= high, got {list(value)!r}")
    return lo, hi


def _count_range(value) -> tuple[int, int] | None:
    if value is None:
        return None
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        value = (value, value)
    ok = (not isinstance(value, (str, bytes, dict)) and hasattr(value, "__len__") and len(value) == 2
          and all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 0 for v in value))
    if not ok or value[0] > value[1]:
        raise ValueError(f"terrain_randomization strips must be [min, max] integers with 0 <= min <= max, or one "
                         f"integer, got {value!r}")
    return int(value[0]), int(value[1])


def _media(value) -> tuple:
    if value is None:
        return ()
    if isinstance(value, (str, Medium)):
        value = [value]
    out = []
    for m in value:
        if isinstance(m, Medium):
            out.append(m)
        elif isinstance(m, str) and m in MEDIA:
            out.append(m)
        else:
            raise unknown("terrain_randomization medium", m, MEDIA)
    return tuple(out)


@dataclass(frozen=True)
class TerrainRandomization:
    """What a sand environment draws at each reset (module docstring: the options and their meaning).

    Made from the environment's ``terrain_randomization`` keyword by :meth:`from_value`; checked here
    (ranges, names); the checks that need the terrain (a medium the law cannot use, a height-field
    surface for ``roughness``, strips shorter than the blend) are :class:`TerrainRandomizer`'s.
    """

    media: tuple = ()
    stress_scale: tuple | None = None
    surface_height: tuple | None = None
    roughness: float = 0.0
    correlation_length: float = 0.05
    strips: tuple | None = None
    strip_length: tuple = (0.2, 0.5)
    strip_start: float = 0.0

    def __post_init__(self):
        s = object.__setattr__
        s(self, "media", _media(self.media))
        s(self, "stress_scale", _range("stress_scale", self.stress_scale, positive=True))
        s(self, "surface_height", _range("surface_height", self.surface_height))
        s(self, "roughness", check_positive("terrain_randomization roughness", self.roughness, allow_zero=True))
        s(self, "correlation_length", check_positive("terrain_randomization correlation_length",
                                                     self.correlation_length))
        s(self, "strips", _count_range(self.strips))
        s(self, "strip_length", _range("strip_length", self.strip_length, positive=True))
        s(self, "strip_start", check_finite("terrain_randomization strip_start", self.strip_start))
        if self.strips is not None and self.strips[1] > 0 and not self.media:
            raise ValueError("terrain_randomization strips need media to draw each strip's medium from; "
                             "add media=[...] (names from mjrft.MEDIA)")

    @property
    def active(self) -> bool:
        """Whether anything is drawn at all."""
        return bool(self.media or self.stress_scale or self.surface_height or self.roughness > 0
                    or (self.strips is not None and self.strips[1] > 0))

    @classmethod
    def from_value(cls, value) -> "TerrainRandomization | None":
        """``None``, a dict of options (the module docstring's keys) or a :class:`TerrainRandomization`; None
        when nothing is drawn."""
        if value is None:
            return None
        if isinstance(value, dict):
            valid = [f.name for f in fields(cls)]
            bad = [k for k in value if k not in valid]
            if bad:
                raise unknown("terrain_randomization option", bad[0], valid)
            value = cls(**value)
        if not isinstance(value, cls):
            raise ValueError("terrain_randomization must be None, a dict of options (media, stress_scale, "
                             "surface_height, roughness, correlation_length, strips, strip_length, strip_start) or "
                             f"a TerrainRandomization, got {type(value).__name__} {value!r}")
        return value if value.active else None


def rough_gain(shape: tuple[int, int], spacing: tuple[float, float],
               correlation_length: float) -> tuple[np.ndarray, tuple[int, int]]:
    """The Fourier gain of :func:`rough_field` (on ``rfft2``'s half plane) for a field of ``shape`` (nrow, ncol)
    with ``spacing`` (dy, dx) m, and the padding (samples per side along y and x): a Gaussian filter on a grid
    padded by two correlation lengths so that opposite borders are uncorrelated."""
    pad = (int(math.ceil(2.0 * correlation_length / spacing[0])),
           int(math.ceil(2.0 * correlation_length / spacing[1])))
    full = (shape[0] + 2 * pad[0], shape[1] + 2 * pad[1])
    ky = 2.0 * np.pi * np.fft.fftfreq(full[0], d=spacing[0])
    kx = 2.0 * np.pi * np.fft.rfftfreq(full[1], d=spacing[1])
    s = 0.5 * correlation_length  # kernel exp(-r^2 / 2 s^2) gives the correlation exp(-r^2 / 4 s^2)
    return np.exp(-0.5 * s * s * (ky[:, None] ** 2 + kx[None, :] ** 2)), pad


def rough_field(rng: np.random.Generator, shape: tuple[int, int], spacing: tuple[float, float], rms: float,
                correlation_length: float) -> np.ndarray:
    """A smooth random height field on a grid of ``shape`` (nrow, ncol) with ``spacing`` (dy, dx) in m: white
    noise filtered with a Gaussian (in Fourier space, on a grid padded by two correlation lengths so that
    opposite borders are uncorrelated), so ``<h(r) h(r + d)> ~ exp(-|d|^2 / correlation_length^2)``, then
    shifted to mean 0 and scaled to RMS exactly ``rms``."""
    if rms == 0.0:
        return np.zeros(shape)
    gain, pad = rough_gain(shape, spacing, correlation_length)
    full = (shape[0] + 2 * pad[0], shape[1] + 2 * pad[1])
    noise = rng.standard_normal(full)
    h = np.fft.irfft2(np.fft.rfft2(noise) * gain, s=full)[pad[0]:pad[0] + shape[0], pad[1]:pad[1] + shape[1]]
    h -= h.mean()
    norm = math.sqrt(float(np.mean(h * h)))
    return h * (rms / norm) if norm > 0 else np.zeros(shape)


def _name(medium) -> str:
    return medium.name if isinstance(medium, Medium) else str(medium)


def _show_one_strip(model: mujoco.MjModel, bed: dict) -> None:
    """Drawn strips replace the scene's: hide its strips' visual boxes (``sand_<k>``, ``water_<k>``, k >= 1) and
    stretch ``sand_surface`` (a box) over the bed they covered, so the rendering shows no layout that is not there."""
    boxes = [g for name, g in bed.items() if name.startswith("sand_") and model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX]
    first = bed.get("sand_surface")
    if first is None or first not in boxes or len(boxes) < 2:
        return
    lo = min(model.geom_pos[g, 0] - model.geom_size[g, 0] for g in boxes)
    hi = max(model.geom_pos[g, 0] + model.geom_size[g, 0] for g in boxes)
    model.geom_pos[first, 0], model.geom_size[first, 0] = (lo + hi) / 2, (hi - lo) / 2
    for name, g in bed.items():
        if name != "sand_surface" and name.split("_")[-1] != "0":
            model.geom_rgba[g, 3] = 0.0


def upload_surface(env, terrain: GranularTerrain) -> None:
    """Send a height-field sand surface that ``terrain`` rewrote to the render contexts ``env`` (a gymnasium
    ``MujocoEnv``) has already made (a context made later reads the model itself)."""
    hfield = terrain.surface_hfield
    viewers = getattr(getattr(env, "mujoco_renderer", None), "_viewers", None)
    if hfield is None or not viewers:
        return
    for viewer in viewers.values():
        viewer.make_context_current()
        mujoco.mjr_uploadHField(env.model, viewer.con, int(env.model.geom_dataid[hfield]))


class TerrainRandomizer:
    """Draws and puts in place a new terrain on one environment's :class:`~mjrft.GranularTerrain` (and the
    visual sand of its model). Made once per environment; checks the options against the terrain.
    ``surface_geoms``: more geoms of the world (a flat floor drawn as the sand) moved up and down with a
    drawn ``surface_height``, besides the scene's own ``sand_*`` / ``water_*`` boxes."""

    def __init__(self, options: TerrainRandomization, terrain: GranularTerrain, model: mujoco.MjModel,
                 surface_geoms=()):
        self.options, self.terrain, self.model = options, terrain, model
        o, t = options, terrain
        self.base_medium, self.base_regions = t.medium, list(t.terrain_model.settings.regions)
        self.base_surface = t.surface if t.surface_hfield is None else t.surface_samples()[2]
        for m in o.media:  # every medium the law can use (an inertial scene needs grain size and density)
            try:
                t.set_medium(m)
            except ValueError as exc:
                raise ValueError(f"terrain_randomization media: {exc}") from None
        t.set_medium(self.base_medium)
        self.spacing = None
        if o.roughness > 0:
            if t.surface_hfield is None:
                raise ValueError("terrain_randomization roughness needs a height-field sand surface: pass "
                                 f"surface_grid=<sample spacing in m> (e.g. {DEFAULT_SURFACE_GRID}) to the environment "
                                 "(the hexapod envs add it by themselves)")
            x, y, _ = t.surface_samples()
            self.spacing = (float(np.hypot(x[1, 0] - x[0, 0], y[1, 0] - y[0, 0])),
                            float(np.hypot(x[0, 1] - x[0, 0], y[0, 1] - y[0, 0])))
            if o.correlation_length < 2.0 * max(self.spacing):
                raise ValueError(f"terrain_randomization correlation_length {o.correlation_length:g} m is shorter "
                                 f"than two samples of the height-field surface ({max(self.spacing):g} m apart); "
                                 f"use correlation_length >= {2 * max(self.spacing):g} m or a finer surface_grid")
        if o.strips is not None and o.strips[1] > 0:
            if t.terrain_model.settings.region_map is not None:
                raise ValueError("terrain_randomization strips cannot replace a region_map; the scene's regions "
                                 "are a map, not strips along x")
            if o.strip_length[0] < t.transition:
                raise ValueError(f"terrain_randomization strip_length {list(o.strip_length)!r} m: strips must be at "
                                 f"least the terrain's transition width {t.transition:g} m long")
        # the scene's visual sand and water boxes (models.scene), moved with the surface (an hfield shows itself)
        bed = {}
        for g in range(model.ngeom):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or ""
            if (model.geom_bodyid[g] == 0 and name.startswith(("sand_", "water_"))
                    and not (model.geom_contype[g] or model.geom_conaffinity[g])):
                bed[name] = g
        shown = [*bed.values(), *(int(g) for g in surface_geoms if int(g) not in bed.values())]
        self._visual = [(g, float(model.geom_pos[g, 2])) for g in shown
                        if o.surface_height is not None and model.geom_type[g] != mujoco.mjtGeom.mjGEOM_HFIELD]
        if o.strips is not None and o.strips[1] > 0:
            _show_one_strip(model, bed)


    def apply(self, rng: np.random.Generator) -> dict:
        """Draw a terrain from ``rng`` and put it in place; returns ``info["terrain"]``."""
        o, t = self.options, self.terrain
        medium = o.media[int(rng.integers(len(o.media)))] if o.media else self.base_medium
        scale = float(rng.uniform(*o.stress_scale)) if o.stress_scale else 1.0
        height = float(rng.uniform(*o.surface_height)) if o.surface_height else 0.0
        field = None
        if o.roughness > 0:
            field = rough_field(rng, self.base_surface.shape, self.spacing, o.roughness, o.correlation_length)
        strips = ()
        if o.strips is not None and o.strips[1] > 0:
            n = int(rng.integers(o.strips[0], o.strips[1] + 1))
            bounds = o.strip_start + np.cumsum(rng.uniform(*o.strip_length, size=n))
            picks = rng.integers(len(o.media), size=n)
            strips = tuple((float(x), _name(o.media[k])) for x, k in zip(bounds, picks))
            t.set_regions([Region(x, o.media[k], t.law) for x, k in zip(bounds, picks)])
        t.set_medium(medium, scale)
        if o.surface_height is not None or field is not None:
            surface = self.base_surface + height
            t.set_surface(surface if field is None else surface + field)
            for g, z in self._visual:
                self.model.geom_pos[g, 2] = z + height
        return {"medium": _name(t.medium), "stress_scale": scale, "surface_height": height,
                "roughness": o.roughness, "strips": strips or tuple((float(r.x_min), r.medium.name)
                                                                     for r in t.regions[1:] if r.x_min is not None)}
