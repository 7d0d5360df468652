"""Any MJX environment on sand: :func:`on_sand` puts an environment whose step calls ``mjx.step`` on granular terrain.

>>> from mujoco_playground import registry
>>> env = registry.load("CheetahRun", config_overrides={"impl": "jax"})
>>> env = mjrft.mjx.on_sand(env, "poppy_cp", stress_scale=(0.5, 1.5))   # then Playground's wrappers, training
>>> state = jax.jit(env.reset)(jax.random.PRNGKey(0))
>>> state = jax.jit(env.step)(state, jnp.zeros(env.action_size))
>>> state.info["sand"].sinkage                                           # per body (m): mjrft.mjx.SandState

The environment is one in MuJoCo Playground's form (``mujoco_playground.MjxEnv``: ``reset(rng) -> State``,
``step(state, action) -> State``, a ``State`` with ``data``, ``obs``, ``reward``, ``done``, ``metrics``, ``info``,
the properties ``mj_model`` and ``mjx_model``, the device model kept in ``_mjx_model``) whose physics goes through
``mujoco.mjx.step`` (Playground's ``mjx_env.step`` does). :class:`SandEnv` is then the same task on sand:

* the terrain: a :class:`mjrft.mjx.Sand` built on the environment's ``mj_model`` (arguments as
  :class:`mjrft.GranularTerrain`; defaults ``floor="auto"``, the floor the robot stands on becomes the sand
  surface, and ``implicit=True``, the implicit granular step, stable at a locomotion task's 2-4 ms physics step)
  BEFORE the model goes to the device: the floor's contacts are removed from ``mj_model`` and the model is put
  again (MJX's JAX implementation), into the environment's ``_mjx_model``;
* the physics: while the environment's ``reset`` and ``step`` are traced, ``mujoco.mjx.step`` is
  :meth:`mjrft.mjx.Sand.step` (the granular wrench added to every physics step, on the model the environment
  steps, so a ``randomization_fn``'s models work), whatever loop the environment runs its physics steps in:
  the terrain's state rides along in ``data.userdata`` (appended after the model's own ``nuserdata`` values by
  ``mjx.make_data`` in ``reset`` and by :meth:`SandEnv.step`, and taken off again before the state is
  returned);
* the state: ``state.info["sand"]`` (:class:`~mjrft.mjx.SandState`: the rest memory, the medium's parameter
  vector, the surface, each body's granular wrench and sinkage, the sticky bad-state record),
  ``info["sand_medium"]`` (an index into :attr:`SandEnv.media`) and ``info["sand_stress_scale"]``;
  ``metrics["sand/diverged"]`` is 1 when the terrain met a non-finite state or force, which also ends the
  episode (``done``); ``metrics["sand/unstable"]`` and ``metrics["sand/out_of_range"]`` are 1 from the step the
  terrain's guards found a stability limit exceeded or chatter, or the law's depth or speed range left, to the
  episode's end (:func:`mjrft.mjx.guards.guard_metrics`; the warnings on the host: :meth:`SandEnv.warn`);
* episodes: each ``reset`` draws the medium uniformly from ``media`` and ``stress_scale`` uniformly from its
  range, from the reset's key (Playground's ``randomization_fn`` changes the ``mjx.Model``, which the sand state
  is not part of). An episode that starts without ``reset`` (Brax's and Playground's auto-reset return a
  finished world to its first ``data`` and keep ``info``) is recognised by ``data.time`` differing from the end
  of the last step: the terrain's memory and its bad-state record are cleared and a new medium and stress scale
  are drawn, so every episode starts on fresh sand;
* contact sensors: every ``contact`` sensor of the model that matches the floor geom (Playground's
  ``<contact geom1="FR" geom2="floor" data="found"/>`` foot sensors) reads the sand instead after every physics
  step: ``found`` is 1 while the body of the sensor's other geom has an element below the surface (its sinkage
  is positive), else 0. The granular force on each body is ``state.info["sand"].wrench`` (:meth:`SandEnv.force`)
  and its sinkage ``state.info["sand"].sinkage`` (:meth:`SandEnv.sinkage`). Contacts read from ``data.contact``
  (and collision helpers that compute them) see no floor: the floor has no contacts on sand.

Refused, each with an error that says why: an environment already wrapped (put the sand on the environment
itself, then Playground's or Brax's wrappers), one already on sand, one without ``mj_model`` (a model only on the
device: the terrain needs the ``mujoco.MjModel`` before ``mjx.put_model``), a device model that still collides
with the floor when it is stepped (put on the device before the terrain removed the floor's contacts), an
environment whose step makes no ``mjx.step`` call, contact sensors with the floor that read more than ``found``.

The patch of ``mujoco.mjx.step`` and ``mujoco.mjx.make_data`` lasts while :meth:`SandEnv.reset` and
:meth:`SandEnv.step` run (Python, at trace time); the compiled functions hold the granular step. Trace them from
one thread at a time.
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence

import jax
import jax.numpy as jnp
import mujoco
import numpy as np
from mujoco import mjx

from ..errors import check_positive
from ..media import get_medium
from .guards import guard_metrics
from .terrain import Sand, SandState

#: the keys :class:`SandEnv` adds to ``state.info`` (``"sand_rng"``: the key of the next episode's draw;
#: ``"sand_time"``: ``data.time`` at the end of the last step)
INFO_KEYS = ("sand", "sand_medium", "sand_stress_scale", "sand_rng", "sand_time")
DIVERGED = "sand/diverged"  # the metric
#: the guards' metrics (:func:`mjrft.mjx.guards.guard_metrics`), 1 from the step a guard fired to the episode's end
GUARD_METRICS = {"unstable": "sand/unstable", "out_of_range": "sand/out_of_range"}
_SALT = 0x5A4D  # folded into the reset key for the terrain's draw (the environment's own draws are unchanged)


def on_sand(env, medium=None, law=None, *, media: Sequence | None = None, stress_scale=None, cull: int | None = None,
            **kwargs) -> "SandEnv":
    """``env`` (MuJoCo Playground's form, its physics through ``mjx.step``) on granular terrain: :class:`SandEnv`.

    ``medium``, ``law`` and ``kwargs`` go to :class:`mjrft.mjx.Sand` (:class:`mjrft.GranularTerrain`'s arguments;
    defaults ``floor="auto"`` and ``implicit=True``); ``cull`` too. ``media``: the media to draw from at each
    episode (names or :class:`~mjrft.Medium`; default the terrain's own medium); ``stress_scale``: a factor on
    every granular stress, a number or a range ``(low, high)`` drawn uniformly at each episode (default 1)."""
    return SandEnv(env, medium, law, media=media, stress_scale=stress_scale, cull=cull, **kwargs)


def _stress_range(stress_scale) -> tuple[float, float]:
    if stress_scale is None:
        return 1.0, 1.0
    if isinstance(stress_scale, (int, float, np.integer, np.floating)) and not isinstance(stress_scale, bool):
        v = check_positive("stress_scale", stress_scale)
        return v, v
    try:
        lo, hi = stress_scale
    except (TypeError, ValueError):
        raise ValueError(f"stress_scale must be a number > 0 or a range (low, high), got {stress_scale!r}") from None
    lo, hi = check_positive("stress_scale low", lo), check_positive("stress_scale high", hi)
    if hi < lo:
        raise ValueError(f"stress_scale range must have low <= high, got {stress_scale!r}")
    return lo, hi


class SandEnv:
    """An environment on sand (see the module docstring); made by :func:`on_sand`. Behaves as the environment
    (its properties and methods are reachable through it) and is the one that Playground's and Brax's wrappers see
    as unwrapped: ``unwrapped`` is itself and its ``_mjx_model`` is the wrapped environment's."""

    def __init__(self, env, medium=None, law=None, *, media=None, stress_scale=None, cull=None, **kwargs):
        if isinstance(env, SandEnv):
            raise ValueError("this environment is already on sand (mjrft.mjx.on_sand was applied to it)")
        inner = getattr(env, "unwrapped", env)
        if inner is not env:
            raise ValueError(f"on_sand got a wrapped environment ({type(env).__name__} around "
                             f"{type(inner).__name__}): put the sand on the environment itself first, then wrap it "
                             "(Playground's wrap_for_brax_training, Brax's training wrappers, a randomization_fn): "
                             "the wrappers keep device models put before the sand removed the floor's contacts")
        model = getattr(env, "mj_model", None)
        if not isinstance(model, mujoco.MjModel):
            raise TypeError(f"on_sand needs the environment's mujoco.MjModel (its mj_model), got "
                            f"{type(model).__name__}: the terrain is built on the MjModel and removes the floor's "
                            "contacts there BEFORE mjx.put_model; a model already on the device cannot be changed")
        if not hasattr(env, "_mjx_model"):
            raise TypeError(f"{type(env).__name__} keeps no _mjx_model: on_sand puts the model on the device again "
                            "into the environment's _mjx_model (MuJoCo Playground's MjxEnv)")
        kwargs.setdefault("floor", "auto")
        kwargs.setdefault("implicit", True)
        self.env = env
        self.sand = Sand(model, medium, law, cull=cull, **kwargs)  # removes the floor's contacts from the MjModel
        if self.sand.ground is not None:
            raise NotImplementedError("on_sand carries the terrain's state in data.userdata, which does not hold the "
                                      "ground memory (ground_memory=True): step mjrft.mjx.Sand with its SandState, "
                                      "or use mjrft's MJX environments (terrain.ground_memory)")
        env._mjx_model = self.sand.put_model()  # ... then to the device
        self.floor = self.sand.terrain_model.settings.floor
        own = self.sand.terrain_model.settings.medium
        chosen = [own] if media is None else list(media)
        if not chosen:
            raise ValueError("media must name at least one medium")
        self._media = tuple(get_medium(m) for m in chosen)
        self.stress_range = _stress_range(stress_scale)
        # each medium's parameter vector as rest + s * stress (Sand.params_of is linear in the stress scale)
        unit = np.stack([self.sand.params_of(m, 1.0) for m in self._media])
        double = np.stack([self.sand.params_of(m, 2.0) for m in self._media])
        self._stress = double - unit
        self._rest = unit - self._stress
        self._sensors = self._floor_sensors(model)
        # the terrain state's layout in data.userdata, after the model's own values: each field of a fresh state
        self._base = int(model.nuserdata)
        self._layout = tuple((k, np.shape(v), np.asarray(v).dtype) for k, v in self.sand.init()._asdict().items()
                             if v is not None)
        self._tail = sum(int(np.prod(s)) for _, s, _ in self._layout)
        self._steps = 0  # mjx.step calls seen while the last reset / step was traced

    # ------------------------------------------------------------------ Playground's MjxEnv interface
    @property
    def unwrapped(self) -> "SandEnv":
        return self

    @property
    def _mjx_model(self):
        return self.env._mjx_model

    @_mjx_model.setter
    def _mjx_model(self, value):  # Playground's domain-randomisation wrapper swaps the model per world here
        self.env._mjx_model = value

    @property
    def mj_model(self) -> mujoco.MjModel:
        return self.env.mj_model

    @property
    def mjx_model(self):
        return self.env.mjx_model

    @property
    def action_size(self) -> int:
        return self.env.action_size

    @property
    def observation_size(self):
        return self.env.observation_size  # the sand changes no observation

    def __getattr__(self, name):  # dt, sim_dt, n_substeps, xml_path, render, the task's own helpers
        if name in ("env", "__setstate__"):
            raise AttributeError(name)
        return getattr(self.env, name)

    @property
    def media(self) -> tuple[str, ...]:
        """The names of the media that ``info["sand_medium"]`` indexes."""
        return tuple(m.name for m in self._media)

    def reset(self, rng: jax.Array):
        """The environment's reset with the terrain's state in ``info`` (medium and stress scale drawn from
        ``fold_in(rng, ...)``, so the environment's own draws are those of the rigid environment)."""
        key, nxt = jax.random.split(jax.random.fold_in(rng, _SALT))
        first, medium, scale = self._draw(key)
        self._steps = 0
        with self._patched(first):
            state = self.env.reset(rng)
        data, sand = self._unpack(state.data, "reset")
        info = dict(state.info)
        info.update(sand=sand, sand_medium=medium, sand_stress_scale=scale, sand_rng=nxt, sand_time=data.time)
        metrics = {**state.metrics, DIVERGED: jnp.zeros(()), **{v: jnp.zeros(()) for v in GUARD_METRICS.values()}}
        return state.replace(data=data, info=info, metrics=metrics)

    def step(self, state, action: jax.Array):
        """The environment's step on sand; a world whose ``data`` no longer follows from the last step (an
        auto-reset) starts on fresh sand with a new draw."""
        info = dict(state.info)
        sand = info["sand"]
        fresh = state.data.time != info["sand_time"]
        key, nxt = jax.random.split(info["sand_rng"])
        new = self._draw(key)
        old = (sand, info["sand_medium"], info["sand_stress_scale"])
        sand, medium, scale = jax.tree_util.tree_map(lambda a, b: jnp.where(fresh, a, b).astype(b.dtype), new, old)
        info.update(sand_medium=medium, sand_stress_scale=scale, sand_rng=jnp.where(fresh, nxt, info["sand_rng"]))
        for k in ("sand", "sand_time"):
            info.pop(k)
        self._steps = 0
        with self._patched(None):
            out = self.env.step(state.replace(data=self._pack(state.data, sand), info=info), action)
        if self._steps == 0:
            raise RuntimeError(f"{type(self.env).__name__}.step made no mujoco.mjx.step call: on_sand puts the "
                               "physics of mjx.step on sand (Playground's mjx_env.step calls it)")
        data, sand = self._unpack(out.data, "step")
        bad = sand.bad_body != -1
        info = dict(out.info)
        info.update(sand=sand, sand_time=data.time)
        metrics = {**out.metrics, DIVERGED: bad.astype(jnp.float32),
                   **{GUARD_METRICS[k]: v for k, v in guard_metrics(sand).items()}}
        done = jnp.maximum(out.done, bad.astype(out.done.dtype))
        return out.replace(data=data, done=done, info=info, metrics=metrics)

    # ------------------------------------------------------------------ what the sand gives
    def _body_ids(self, bodies) -> np.ndarray:
        m = self.mj_model
        ids = []
        for b in [bodies] if isinstance(bodies, (str, int, np.integer)) else bodies:
            i = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, b) if isinstance(b, str) else int(b)
            if not 0 <= i < m.nbody:
                names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, k) for k in range(m.nbody)]
                raise ValueError(f"unknown body {b!r}; bodies: {', '.join(n or '#' for n in names)}")
            ids.append(i)
        return np.array(ids, dtype=np.int32)

    def sinkage(self, state, bodies) -> jax.Array:
        """Deepest element of each of ``bodies`` (names or ids) below the surface after the last physics step (m)."""
        return state.info["sand"].sinkage[..., self._body_ids(bodies)]

    def warn(self, state) -> None:
        """On the host, for ``state`` (one world or a batch): warn for what the terrain's guards recorded since each
        world's episode began (:meth:`mjrft.mjx.Sand.warn`)."""
        self.sand.warn(state.info["sand"], stacklevel=4)

    def force(self, state, bodies) -> jax.Array:
        """Granular force on each of ``bodies`` applied by the last physics step (N, world frame; (..., k, 3))."""
        return state.info["sand"].wrench[..., self._body_ids(bodies), :3]

    def check(self, state) -> None:
        """Raise :class:`~mjrft.NonFiniteError` naming the body and time of a world whose terrain met a non-finite
        state or force (:meth:`mjrft.mjx.Sand.check`)."""
        self.sand.check(state.info["sand"])

    # ------------------------------------------------------------------ pieces
    def _draw(self, key):
        """(a fresh terrain state, the medium's index, the stress scale) drawn from ``key``."""
        k_med, k_scale = jax.random.split(key)
        medium = jax.random.randint(k_med, (), 0, len(self._media))
        lo, hi = self.stress_range
        scale = jax.random.uniform(k_scale, (), minval=lo, maxval=hi) if hi > lo else jnp.asarray(lo, jnp.float32)
        params = jnp.asarray(self._rest)[medium] + scale * jnp.asarray(self._stress)[medium]
        return self.sand.init(params=params), medium, scale

    def _pack(self, d, s: SandState):
        dtype = d.userdata.dtype
        tail = jnp.concatenate([jnp.ravel(getattr(s, k)).astype(dtype) for k, _, _ in self._layout])
        return d.replace(userdata=jnp.concatenate([d.userdata, tail]))

    def _unpack(self, d, where: str):
        ud = d.userdata
        if ud.shape[-1] != self._base + self._tail:
            raise RuntimeError(f"{type(self.env).__name__}.{where} handed on an mjx.Data without the terrain's state "
                               f"(userdata of {ud.shape[-1]} values, {self._base} + {self._tail} expected): on_sand "
                               "needs the environment's data made by mjx.make_data in reset and carried from step to "
                               "step")
        out, i = {}, self._base
        for k, shape, kind in self._layout:  # each field back in its own shape and type (integers rounded)
            size = int(np.prod(shape))
            value = ud[i:i + size].reshape(shape)
            out[k] = jnp.round(value).astype(kind) if np.issubdtype(kind, np.integer) else value
            i += size
        return d.replace(userdata=ud[:self._base]), SandState(**out)

    def _floor_sensors(self, model) -> tuple[np.ndarray, np.ndarray]:
        """(sensordata addresses, dims, bodies) of the contact sensors that match the floor geom."""
        adr, dim, body = [], [], []
        if self.floor is None:
            return np.zeros(0, np.int32), np.zeros(0, np.int32), np.zeros(0, np.int32)
        geom = int(mujoco.mjtObj.mjOBJ_GEOM)
        has_elements = set(np.asarray(self.sand.body_ids).tolist())
        for s in range(model.nsensor):
            if model.sensor_type[s] != mujoco.mjtSensor.mjSENS_CONTACT:
                continue
            sides = [(int(model.sensor_objtype[s]), int(model.sensor_objid[s])),
                     (int(model.sensor_reftype[s]), int(model.sensor_refid[s]))]
            if (geom, self.floor) not in sides:
                continue
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SENSOR, s) or f"#{s}"
            kind, oid = sides[1] if sides[0] == (geom, self.floor) else sides[0]
            if kind == geom:
                b = int(model.geom_bodyid[oid])
            elif kind == int(mujoco.mjtObj.mjOBJ_BODY):
                b = oid
            else:
                raise NotImplementedError(f"contact sensor {name!r} matches the floor with a "
                                          f"{mujoco.mjtObj(kind).name}; on sand it can match a geom or a body")
            if int(model.sensor_intprm[s, 0]) != 1:
                raise NotImplementedError(f"contact sensor {name!r} reads more than 'found' of the contacts with the "
                                          "floor; on sand it reads 'found' only (the granular force and sinkage of "
                                          "each body are in state.info['sand'].wrench / .sinkage)")
            if b not in has_elements:
                bname = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"#{b}"
                raise ValueError(f"contact sensor {name!r} matches the floor with body {bname!r}, which has no sand "
                                 "elements (select its geoms with bodies= / geoms=)")
            adr.append(int(model.sensor_adr[s]))
            dim.append(int(model.sensor_dim[s]))
            body.append(b)
        return np.array(adr, np.int32), np.array(dim, np.int32), np.array(body, np.int32)

    @property
    def contact_sensors(self) -> tuple[str, ...]:
        """The names of the contact sensors that read the sand."""
        m = self.mj_model
        by_adr = {int(m.sensor_adr[s]): s for s in range(m.nsensor)}
        return tuple(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_SENSOR, by_adr[int(a)]) for a in self._sensors[0])

    def _write_sensors(self, d, s: SandState):
        adr, dim, body = self._sensors
        if adr.size == 0:
            return d
        found = (s.sinkage[body] > 0.0).astype(d.sensordata.dtype)
        idx = np.concatenate([a + np.arange(k) for a, k in zip(adr, dim)])
        val = jnp.concatenate([jnp.broadcast_to(found[i], (k,)) for i, k in enumerate(dim)])
        return d.replace(sensordata=d.sensordata.at[idx].set(val))

    def _check_floor(self, m) -> None:
        contype, conaff = m.geom_contype, m.geom_conaffinity
        if isinstance(contype, np.ndarray) and isinstance(conaff, np.ndarray) and self.floor is not None and (
                contype[self.floor] or conaff[self.floor]):
            raise ValueError("the mjx.Model being stepped still collides with the floor: it was put on the device "
                             "before the sand removed the floor's contacts (a randomization_fn's models, or a "
                             "model kept from before on_sand); build them from env.mjx_model after on_sand")

    @contextlib.contextmanager
    def _patched(self, first: SandState | None):
        """``mujoco.mjx.step`` as the granular step (and, with ``first``, ``mujoco.mjx.make_data`` carrying the
        terrain state ``first``) for the duration."""
        step, make_data = mjx.step, mjx.make_data

        def sand_step(m, d):
            self._steps += 1
            self._check_floor(m)
            d, s = self._unpack(d, "physics step")
            mjx.step = step  # the granular step's own calls (impl="warp") are MJX's
            try:
                d, s = self.sand.step(m, d, s)
            finally:
                mjx.step = sand_step
            return self._pack(self._write_sensors(d, s), s)

        def sand_make_data(*args, **kwargs):
            return self._pack(make_data(*args, **kwargs), first)

        mjx.step = sand_step
        if first is not None:
            mjx.make_data = sand_make_data
        try:
            yield
        finally:
            mjx.step, mjx.make_data = step, make_data
