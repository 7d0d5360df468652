"""Any gymnasium MuJoCo environment on sand: :class:`GranularWrapper`.

>>> import gymnasium, mjrft
>>> env = mjrft.envs.GranularWrapper(gymnasium.make("Ant-v5"), medium="poppy_lp")
>>> env = gymnasium.make("mjrft/AntSand-v5", medium="poppy_lp")        # the same, registered

The env's own code is not changed. The wrapper

* builds a :class:`mjrft.GranularTerrain` on the env's loaded model with ``floor="auto"`` (the world's
  plane, box or height-field floor becomes the sand surface at its height and its rigid contacts are
  removed in the loaded model, never in the file) and ``resolution="auto"``; ``medium``, ``law`` and
  every other keyword argument of :class:`~mjrft.GranularTerrain` (``bodies``, ``geoms``, ``resolution``,
  ...) are passed on;
* replaces the physics of the unwrapped env (its ``_step_mujoco_simulation``, which gymnasium's
  ``MujocoEnv.do_simulation`` calls) on this instance only, by ``terrain.step`` over the same simulated
  time, then MuJoCo's ``mj_rnePostConstraint`` (as gymnasium does) and the sand's wrench added to
  ``data.cfrc_ext`` (below): no process-wide MuJoCo callback, so any number of sand envs and plain envs
  live side by side;
* sub-steps (below), so that ``env.dt``, ``frame_skip`` and the control period are the env's own;
* reports ``info["sinkage"]`` (m, deepest element below the surface) and ``info["granular_force"]``
  (N, world frame) of each selected body (order :attr:`GranularWrapper.body_names`) and
  ``info["substeps"]`` (physics steps per model step used in this env step);
* ends the episode when the simulation diverges (:class:`mjrft.NonFiniteError`: a non-finite granular
  force or state, or MuJoCo resetting a state it found non-finite or huge): that step returns
  ``terminated=True``, reward 0 and ``info["diverged"]`` with the error message (body and time); the
  physics stays stopped until ``reset()``, so an episode never goes on from MuJoCo's reset state;
* renders the sand: the floor geom (now the sand surface) is drawn in ``sand_rgba``, translucent by
  default so buried parts of the robot stay visible (``sand_rgba=None`` keeps the env's own colour);
* refuses an action that is not of the action space's shape or holds NaN or infinite values with a
  ``ValueError`` naming it, before anything is simulated (as mjrft's own envs do);
* draws a new terrain at each ``reset()`` with ``terrain_randomization`` (as mjrft's own sand envs,
  :mod:`mjrft.envs.randomization`): medium, stress scale, surface height and strips from the env's
  ``np_random`` after its own reset noise, so ``reset(seed=s)`` reproduces it; ``info["terrain"]`` (at reset
  and in every step's info) says what was drawn, and a flat floor drawn as the sand moves with a drawn
  surface height. ``roughness`` needs a height-field floor. Off (the default), nothing is drawn and the env
  steps the same trajectory;
* warns (:class:`mjrft.SandContactWarning`, from its terrain: :func:`mjrft.reach.reach_warning`) at
  construction when the robot may never meet the sand: no selected geom is below the surface at the model's
  initial pose and none can fall onto it (no free joint, or slide joint with a vertical component, under a
  gravity pointing down). The warning lists each geom's lowest point and the lowest point any motion of its
  joints can bring it to (:func:`mjrft.reach.lowest_reach`, a bound), and says whether none can reach the sand
  at all (InvertedDoublePendulum's floor lies 3 m below it) or the robot is fixed to the world and feels the
  grains only where its actuators push a geom down (Pusher, in zero gravity above its table). A model whose geoms are all visual-only (Swimmer) is refused
  by the terrain with an error naming them;
* is a ``gymnasium.utils.RecordConstructorArgs``: ``env.spec`` records the wrapper and its arguments, so
  ``gymnasium.make(env.spec)`` rebuilds the env on sand and gymnasium's ``check_env`` accepts it.

Integrators. ``terrain.step`` is MuJoCo's ``mj_step1`` / granular wrench / ``mj_step2``, which cannot
split an RK4 step (MuJoCo integrates it with Euler). An RK4 model (four of gymnasium's five robots) is
therefore switched to MuJoCo's semi-implicit Euler in the loaded model and sub-stepped like any other;
``implicit`` and ``implicitfast`` models keep their integrator. :attr:`GranularWrapper.integrator` names
what runs.

Granular step. The terrain is built with ``implicit=True`` (:mod:`mjrft.implicit_step`; docs/numerics.md,
"Implicit step"): the grains' springs (the rest regularisation below yield, whose explicit limit is a few
milliseconds for a light foot carrying a heavy robot) are integrated implicitly, so the internal step is
chosen for accuracy rather than stability; ``implicit=False`` gives the explicit step and its stability rule below.

Sub-stepping rule (``substeps="auto"``). Each env step the model's timestep ``h`` is split into
``k = ceil(h / dt_s)`` equal internal steps (``1 <= k <= max_substeps``). Two limits enter: the
springs', the smaller of :func:`static_timestep_limit` (their explicit limit when any one selected body
carries the robot's whole weight at yield, in the env's initial pose: a load any foot may meet at the
next step) and the terrain's at the end of the previous env step, and the depth stiffness's at the end of
the previous env step (:meth:`mjrft.GranularTerrain.stable_timestep`, ``part="springs"`` and
``"depth"``; after a reset only the static one):

* implicit step (default): ``dt_s = min(spring_step / omega, SAFETY x depth limit)``: ``omega`` the rate
  of the stiffest granular spring (:func:`spring_rate` of the springs' explicit limit), ``spring_step = 1``
  (one radian of it per step), and the limit of the depth stiffness, which stays explicit (``part="depth"``);
* explicit step (``implicit=False``): ``dt_s = SAFETY x`` the smaller of the springs' and the depth
  stiffness's limits, ``SAFETY = 0.5``.

The env step then runs ``frame_skip x k`` physics steps of ``h / k``; ``model.opt.timestep`` is ``h``
again between steps. The rule depends only on the state, so a seeded episode is reproducible.
``substeps=k`` fixes ``k``. The terrain's :class:`~mjrft.TerrainStabilityWarning` still reports a step
beyond a limit (an impact stiffer than the previous env step's state, or a limit below
``h / max_substeps``).

What ``spring_step`` trades (``python benchmarks/implicit_accuracy.py``, output in
``benchmarks/results/implicit_accuracy.txt``): on gymnasium's five robots, 1 s of random actions against
the explicit step at 0.1 ms, ``spring_step = 1`` takes 1-3 sub-steps where the explicit rule takes 1-6
(HalfCheetah 3.05 against 6.1, Humanoid 2 against 5, Ant 3 against 5); its errors are 1.2-4x the explicit
rule's on HalfCheetah, Humanoid and Ant (net vertical force 4.5 % and 6 % of the weight RMS on
HalfCheetah and Humanoid; Ant's impacts are poorly resolved by either, 48 % and 122 %), and smaller on
Walker2d; ``spring_step = 0.5`` takes as many sub-steps as the explicit rule with equal or smaller
position errors. Bench numbers: ``benchmarks/bench_third_party.py``.

``cfrc_ext``. MuJoCo's ``cfrc_ext`` of a body is its external spatial force (torque first, then force)
about the centre of mass of the body's kinematic tree (``subtree_com`` of its root), world frame, as
``mj_rnePostConstraint`` computes it from contacts and ``xfrc_applied``. The wrapper adds the sand's
wrench of the step's last physics step to it in the same convention (torque ``t + (xipos - c) x f``),
so observations and costs built from ``cfrc_ext`` (Ant's, Humanoid's) see the sand.
"""

from __future__ import annotations

import inspect
import math
import warnings

import gymnasium
import mujoco
import numpy as np
from gymnasium.envs.mujoco import MujocoEnv
from numba import njit

from mjrft.coupler import GranularTerrain
from mjrft.floor import geom_world_boxes
from mjrft.stability import max_stable_dt
from mjrft.errors import NonFiniteError, unknown

from .randomization import TerrainRandomization, TerrainRandomizer, upload_surface

__all__ = ["GranularWrapper", "SAND_RGBA", "SAFETY", "SPRING_STEP", "spring_rate", "static_timestep_limit",
           "terrain_option_names"]

#: colour of the sand surface as rendered (the floor geom's rgba; translucent, so buried parts show)
SAND_RGBA = (0.76, 0.64, 0.42, 0.6)
#: fraction of the stable timestep the automatic sub-step uses (the module docstring's rule)
SAFETY = 0.5
#: with the implicit step, the automatic sub-step resolves the stiffest granular spring: ``omega dt <= SPRING_STEP``
SPRING_STEP = 1.0
MAX_SUBSTEPS = 64
WRAPPER_OPTIONS = ("substeps", "max_substeps", "spring_step", "sand_rgba", "terrain_randomization")
#: m: a selected geom counts as in the sand, or as reaching it, below the surface by more than this


def spring_rate(limit: float, tau: float) -> float:
    """The angular rate ``omega`` (1/s) of the granular spring whose explicit stability limit is ``limit`` (s)
    with damping time ``tau`` (s): the inverse of :func:`mjrft.stability.max_stable_dt`'s
    ``limit = 2 (sqrt(1 + zeta^2) - zeta) / omega``, ``zeta = tau omega / 2``, i.e.
    ``omega = 2 / sqrt(limit (limit + 2 tau))`` (0 for an infinite limit)."""
    if not math.isfinite(limit):
        return 0.0
    return 2.0 / math.sqrt(limit * (limit + 2.0 * tau))


def terrain_option_names() -> list[str]:
    """The keyword arguments of :class:`mjrft.GranularTerrain` that :class:`GranularWrapper` passes on."""
    params = inspect.signature(GranularTerrain.__init__).parameters
    return [n for n, p in params.items() if p.kind is p.KEYWORD_ONLY]


def static_timestep_limit(terrain: GranularTerrain, data: mujoco.MjData) -> float:
    """Largest stable timestep (s) when any one selected body carries the robot's whole weight at yield.

    For body ``b``: stiffness ``K = M g / delta`` (``M`` the model's total mass, ``delta`` the yield
    displacement), damper ``tau K`` (the terrain's ``damping_time``) and inverse mass ``w`` the largest
    eigenvalue of the translational mobility of ``b``'s centre of mass in ``data``'s pose
    (:meth:`GranularTerrain.inverse_mass`); the limit is :func:`mjrft.stability.max_stable_dt` of the stiffest
    body. With ``yield_displacement = 0`` the viscous mode ``c = M g / v_eps`` is used instead. ``data`` is
    forwarded (``mj_forward``) first: pass a scratch ``MjData`` holding the pose to judge."""
    m = terrain.model
    weight = float(m.body_subtreemass[0]) * max(0.0, -float(m.opt.gravity[2]))
    if weight <= 0.0:
        return math.inf
    out = math.inf
    mujoco.mj_forward(m, data)
    for b in terrain.body_ids:
        w = terrain.inverse_mass(data, int(b))
        if not w > 0.0:  # a body that cannot move (welded to the world) has no limit
            continue
        if terrain.yield_displacement > 0:
            K = weight / terrain.yield_displacement
            out = min(out, max_stable_dt(K, terrain.damping_time * K, w))
        else:
            out = min(out, max_stable_dt(0.0, weight / terrain.v_eps, w))
    return out


@njit(cache=True, error_model="numpy")
def _add_wrench_to_cfrc_ext(cfrc_ext, xipos, subtree_com, wrench, bodies, roots):
    """``cfrc_ext[b] += (t + (xipos[b] - subtree_com[root]) x f, f)`` for each body (MuJoCo's convention)."""
    for i in range(bodies.shape[0]):
        b, c = bodies[i], roots[i]
        fx, fy, fz = wrench[b, 0], wrench[b, 1], wrench[b, 2]
        rx, ry, rz = xipos[b, 0] - subtree_com[c, 0], xipos[b, 1] - subtree_com[c, 1], xipos[b, 2] - subtree_com[c, 2]
        cfrc_ext[b, 0] += wrench[b, 3] + ry * fz - rz * fy
        cfrc_ext[b, 1] += wrench[b, 4] + rz * fx - rx * fz
        cfrc_ext[b, 2] += wrench[b, 5] + rx * fy - ry * fx
        cfrc_ext[b, 3] += fx
        cfrc_ext[b, 4] += fy
        cfrc_ext[b, 5] += fz


@njit(cache=True, error_model="numpy")
def _body_sinkage(depth, elem_body, slot, out):
    """Deepest element depth (>= 0) per body: ``out[slot[elem_body[e]]]``."""
    out[:] = 0.0
    for e in range(depth.shape[0]):
        j = slot[elem_body[e]]
        if depth[e] > out[j]:
            out[j] = depth[e]


def _all_finite(a: np.ndarray) -> bool:
    """Whether every entry of the numeric array ``a`` is finite. An env step's action has a few entries, for
    which numpy's ``isfinite`` and ``all`` cost ~3 us; a float32/float64 array is checked in Python (exact:
    its values convert to Python floats unchanged), integers are always finite."""
    kind = a.dtype.kind
    if kind in "iu":
        return True
    if kind == "f" and a.dtype.itemsize <= 8:
        return all(map(math.isfinite, a.ravel().tolist()))
    return bool(np.all(np.isfinite(a)))


@njit(cache=True, error_model="numpy")
def _sinkage_and_force(depth, g_start, g_active, elem_body, slot, wrench, bodies, sink, force):
    """:func:`_body_sinkage` into ``sink`` (zeros, one per body of ``bodies``) and ``wrench[bodies, :3]`` into
    ``force``, in one compiled call (each env step's info; the caller makes the new arrays, which costs less than
    returning arrays made here). Only the elements of the cull groups the kernel evaluated last (``g_active``;
    ``g_start`` their first elements) are read: the kernel zeroes the depth of a group it skips, so the others
    hold 0."""
    for g in range(g_active.shape[0]):
        if g_active[g]:
            for e in range(g_start[g], g_start[g + 1]):
                j = slot[elem_body[e]]
                if depth[e] > sink[j]:
                    sink[j] = depth[e]
    for i in range(bodies.shape[0]):
        for j in range(3):
            force[i, j] = wrench[bodies[i], j]


def _plain(value):
    """``value`` with numpy arrays and scalars as lists and Python numbers: the wrapper's recorded arguments (its
    ``spec``), which gymnasium compares with ``==`` when it rebuilds an env from a spec."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value


def _build_terrain(model: mujoco.MjModel, medium, law, options: dict) -> tuple[GranularTerrain, list[int]]:
    """The terrain on ``model`` (``floor="auto"``, ``resolution="auto"`` unless given: ``resolution_scale`` alone
    scales the ``"auto"`` size) and the floor geoms."""
    options = dict(options)
    options.setdefault("floor", "auto")
    if "resolution_scale" not in options:
        options.setdefault("resolution", "auto")
    options.setdefault("implicit", True)
    terrain = GranularTerrain(model, medium, law, **options)
    floor = getattr(terrain, "floor", None)
    return terrain, ([int(floor)] if floor is not None else [])


class GranularWrapper(gymnasium.Wrapper, gymnasium.utils.RecordConstructorArgs):
    """A gymnasium ``MujocoEnv`` on granular terrain (see the module docstring).

    Args:
        env: a gymnasium env whose ``unwrapped`` is a ``gymnasium.envs.mujoco.MujocoEnv`` (not already on
            sand, not one of mjrft's own envs, which have their terrain built in).
        medium, law: the terrain's medium and law (:class:`mjrft.GranularTerrain`).
        substeps: ``"auto"`` (the module's rule) or a fixed integer ``k >= 1`` of physics steps per model step.
        max_substeps: the largest ``k`` the automatic rule uses (default 64).
        spring_step: with the implicit step, the automatic rule's ``omega dt`` for the stiffest granular spring
            (default :data:`SPRING_STEP` = 1; smaller is more accurate and slower, see the module docstring).
        sand_rgba: colour of the floor geom that is the sand surface (4 numbers in [0, 1]); ``None`` keeps it.
        terrain_randomization: ``None`` (default: the same terrain every episode, nothing drawn), a dict of
            options or a :class:`mjrft.envs.randomization.TerrainRandomization`: a new terrain drawn at each
            ``reset()`` from the env's ``np_random`` (medium, stress scale, surface height, strips; roughness
            needs a height-field floor), reported in ``info["terrain"]``; :mod:`mjrft.envs.randomization`.
        **terrain_options: keyword arguments of :class:`mjrft.GranularTerrain` (``bodies``, ``geoms``,
            ``floor``, ``resolution``, ``surface``, ``yield_displacement``, ...).
    """

    def __init__(self, env: gymnasium.Env, medium=None, law=None, *, substeps="auto", max_substeps: int = MAX_SUBSTEPS,
                 spring_step: float = SPRING_STEP, sand_rgba=SAND_RGBA, terrain_randomization=None,
                 **terrain_options):
        if not isinstance(env, gymnasium.Env):
            raise TypeError(f"GranularWrapper wraps a gymnasium.Env, got {type(env).__name__}")
        u = env.unwrapped
        if not isinstance(u, MujocoEnv):
            raise TypeError(f"GranularWrapper needs a gymnasium MuJoCo environment (gymnasium.envs.mujoco.MujocoEnv); "
                            f"{type(u).__name__} is not one")
        if getattr(u, "terrain", None) is not None or type(u).__module__.startswith("mjrft."):
            raise ValueError(f"{type(u).__name__} is one of mjrft's own environments with its terrain built in; "
                             "use it directly (its sand= / medium= / law= arguments)")
        if "_step_mujoco_simulation" in vars(u):
            raise ValueError(f"this {type(u).__name__} is already on sand (wrapped by a GranularWrapper) or its physics "
                             "was replaced by other code; wrap the env only once")
        valid = terrain_option_names() + ["floor"]
        for name in terrain_options:
            if name not in valid:
                raise unknown("GranularWrapper option", name, valid + list(WRAPPER_OPTIONS) + ["medium", "law"])
        if substeps != "auto" and (isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer))
                                   or substeps < 1):
            raise ValueError(f"substeps must be 'auto' or an integer >= 1, got {substeps!r}")
        if isinstance(max_substeps, bool) or not isinstance(max_substeps, (int, np.integer)) or max_substeps < 1:
            raise ValueError(f"max_substeps must be an integer >= 1, got {max_substeps!r}")
        if (isinstance(spring_step, bool) or not isinstance(spring_step, (int, float, np.integer, np.floating))
                or not (math.isfinite(spring_step) and spring_step > 0)):
            raise ValueError(f"spring_step must be a finite number > 0 (omega dt of the stiffest granular spring), "
                             f"got {spring_step!r}")
        if sand_rgba is not None:
            rgba = np.asarray(sand_rgba, dtype=float) if np.ndim(sand_rgba) == 1 else None
            if rgba is None or rgba.shape != (4,) or not np.all((rgba >= 0) & (rgba <= 1)):
                raise ValueError(f"sand_rgba must be 4 numbers in [0, 1] (red, green, blue, alpha) or None, "
                                 f"got {sand_rgba!r}")
        randomization = TerrainRandomization.from_value(terrain_randomization)
        gymnasium.utils.RecordConstructorArgs.__init__(  # gymnasium.make(env.spec) rebuilds the wrapper from these
            self, **{k: _plain(v) for k, v in dict(
                medium=medium, law=law, substeps=substeps, max_substeps=max_substeps, spring_step=spring_step,
                sand_rgba=sand_rgba, terrain_randomization=terrain_randomization, **terrain_options).items()})
        super().__init__(env)
        model, data = u.model, u.data
        integrator = model.opt.integrator
        self.integrator = mujoco.mjtIntegrator(integrator).name
        if integrator == mujoco.mjtIntegrator.mjINT_RK4:
            model.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER  # what mj_step1/mj_step2 run; now explicit
            self.integrator = f"mjINT_EULER (the model's {self.integrator} cannot be split by mj_step1/mj_step2)"
        contacts = (model.geom_contype.copy(), model.geom_conaffinity.copy(), model.pair_margin.copy())
        try:
            self.terrain, self.floor_geoms = _build_terrain(model, medium, law, terrain_options)
            self.randomizer = None if randomization is None else self._randomizer(randomization, model)
        except BaseException:  # a refused setting leaves the env as it was
            model.opt.integrator = integrator
            model.geom_contype[:], model.geom_conaffinity[:], model.pair_margin[:] = contacts
            raise
        self.terrain_info: dict | None = None  # info["terrain"] of this episode (with terrain_randomization)
        if sand_rgba is not None:
            for g in self.floor_geoms:
                model.geom_rgba[g] = sand_rgba
        self.substeps = substeps if substeps == "auto" else int(substeps)
        self.max_substeps = int(max_substeps)
        self.spring_step = float(spring_step)  # the implicit rule's omega dt (module docstring)
        self.body_ids = np.asarray(self.terrain.body_ids, dtype=np.int64)
        self.body_names = tuple(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, int(b)) or f"#{b}"
                                for b in self.body_ids)
        self._root = np.asarray(model.body_rootid[self.body_ids], dtype=np.int64)
        self._slot = np.zeros(model.nbody, dtype=np.int64)  # body id -> its row in info["sinkage"]
        self._slot[self.body_ids] = np.arange(len(self.body_ids))
        self.model_timestep = float(model.opt.timestep)
        self.diverged: str | None = None
        self.last_substeps = 1
        scratch = mujoco.MjData(model)
        scratch.qpos[:], scratch.qvel[:] = u.init_qpos, 0.0
        mujoco.mj_kinematics(model, scratch)
        self._static_limit = static_timestep_limit(self.terrain, scratch)
        self._limit = self._static_limit
        self._depth_limit = math.inf  # implicit step: the explicit limit of the depth stiffness (module docstring)
        self._model, self._data = model, data  # the env's own, for the life of the env
        self._opt = model.opt  # its options (a view of the model's struct): set twice per env step
        u._step_mujoco_simulation = self._physics  # this instance only (see the module docstring)

    def _randomizer(self, options: TerrainRandomization, model: mujoco.MjModel) -> TerrainRandomizer:
        """The terrain randomiser of this env; the floor geom (drawn as the sand) moves with a drawn surface height."""
        if options.roughness > 0 and self.terrain.surface_hfield is None:
            floor = ("" if self.terrain.floor is None else
                     f": this env's sand surface is the flat top of its floor geom "
                     f"'{mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, self.terrain.floor)}'")
            raise ValueError("terrain_randomization roughness needs a height-field sand surface" + floor + "; wrap "
                             "an env whose floor is an hfield geom (floor='auto' takes it as the surface) or name "
                             "one (surface='<hfield geom>')")
        shown = [g for g in self.floor_geoms  # a flat floor of the world body (an hfield shows the drawn field)
                 if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_HFIELD and model.geom_bodyid[g] == 0]
        return TerrainRandomizer(options, self.terrain, model, surface_geoms=shown)

    # ------------------------------------------------------------------ physics
    def _next_substeps(self) -> int:
        if self.substeps != "auto":
            return self.substeps
        if self.terrain.implicit:
            rate = spring_rate(self._limit, self.terrain.damping_time)
            dt_s = min(self.spring_step / rate if rate > 0.0 else math.inf, SAFETY * self._depth_limit)
        else:
            dt_s = SAFETY * min(self._limit, self._depth_limit)
        return int(min(self.max_substeps, max(1, math.ceil(self.model_timestep / dt_s - 1e-9))))

    def _physics(self, ctrl, n_frames) -> None:
        """The env's ``_step_mujoco_simulation``: ``n_frames`` model steps on sand, sub-stepped."""
        data = self._data
        data.ctrl[:] = ctrl
        if self.diverged is not None:  # stopped until reset(): never go on from MuJoCo's reset state
            return
        k = self._next_substeps()
        self.last_substeps = k
        try:
            self._opt.timestep = self.model_timestep / k
            self.terrain.step(data, int(n_frames) * k)
        except NonFiniteError as exc:
            self.diverged = str(exc)
        finally:
            self._opt.timestep = self.model_timestep
        mujoco.mj_rnePostConstraint(self._model, data)
        if self.diverged is None:
            self._add_cfrc_ext(data)
            self._update_limit(data)

    def _update_limit(self, data) -> None:
        if self.substeps == "auto":
            springs, self._depth_limit = self.terrain.min_stable_timesteps(data)
            self._limit = min(springs, self._static_limit)

    def _add_cfrc_ext(self, data) -> None:
        """Add the sand's wrench (force, torque about each body's CoM) to ``cfrc_ext`` in MuJoCo's convention."""
        _add_wrench_to_cfrc_ext(data.cfrc_ext, data.xipos, data.subtree_com, self.terrain.wrench, self.body_ids,
                                self._root)

    # ------------------------------------------------------------------ measurements
    def sinkage(self) -> np.ndarray:
        """Deepest element depth (m, >= 0) of each selected body (order :attr:`body_names`)."""
        out = np.zeros(len(self.body_ids))
        _body_sinkage(self.terrain.depth, self.terrain.elem_body, self._slot, out)
        return out

    def granular_force(self) -> np.ndarray:
        """Net granular force (N, world frame) on each selected body, shape (n_bodies, 3)."""
        return self.terrain.wrench[self.body_ids, :3].copy()

    def _sand_info(self, info: dict) -> dict:
        tm, st = self.terrain.terrain_model, self.terrain.terrain_state
        n = self.body_ids.shape[0]
        sink, force = np.zeros(n), np.empty((n, 3))
        _sinkage_and_force(st.depth, tm.elements.group_start, st.group_active, tm.elements.body, self._slot, st.wrench,
                           self.body_ids, sink, force)
        info["sinkage"], info["granular_force"] = sink, force
        info["substeps"] = self.last_substeps
        if self.terrain_info is not None:
            info["terrain"] = dict(self.terrain_info)  # a new dict each call, as gymnasium asks
        return info

    # ------------------------------------------------------------------ gym API
    def reset(self, *, seed=None, options=None):
        self.diverged = None
        obs, info = self.env.reset(seed=seed, options=options)
        u = self.env.unwrapped
        if self.randomizer is not None:  # after the env's own reset noise, from its np_random
            self.terrain_info = self.randomizer.apply(u.np_random)
            upload_surface(u, self.terrain)
        self.terrain.reset()
        self.terrain.compute(u.data, 0.0)  # the reset state's sinkage and force (memory empty, not advanced)
        self._limit = self._static_limit
        self._depth_limit = math.inf
        self.last_substeps = self._next_substeps()
        return obs, self._sand_info(dict(info))

    def step(self, action):
        a = np.asarray(action)
        shape = self.action_space.shape
        if a.shape != shape or a.dtype.kind not in "iufcm":  # np.number's kinds
            raise ValueError(f"action must be numbers of shape {shape}, got {a.dtype} of shape {a.shape}")
        if not _all_finite(a):
            raise ValueError(f"action contains NaN or infinite values: {a!r}")
        obs, reward, terminated, truncated, info = self.env.step(action)
        info = self._sand_info(dict(info))
        if self.diverged is not None:
            obs = np.asarray(obs)
            if not np.all(np.isfinite(obs)):
                obs = np.zeros_like(obs)
            reward, terminated = 0.0, True
            info["diverged"] = self.diverged
            info["sinkage"] = np.zeros(len(self.body_ids))
            info["granular_force"] = np.zeros((len(self.body_ids), 3))
        return obs, reward, terminated, truncated, info


# ---------------------------------------------------------------------------------------------- registered ids
def wrapper_option_names() -> list[str]:
    """Keyword arguments of a registered sand variant that go to :class:`GranularWrapper` (the rest go to the env)."""
    return ["medium", "law", *WRAPPER_OPTIONS, "floor", *terrain_option_names()]


def _env_creator(gym_id: str):
    spec = gymnasium.spec(gym_id)
    creator = spec.entry_point
    if isinstance(creator, str):
        from gymnasium.envs.registration import load_env_creator

        creator = load_env_creator(creator)
    return spec, creator


def env_option_names(gym_id: str) -> list[str]:
    """Keyword arguments the gymnasium env ``gym_id`` accepts (its class and ``MujocoEnv``'s)."""
    _, creator = _env_creator(gym_id)
    names = set()
    for fn in (getattr(creator, "__init__", creator), MujocoEnv.__init__):
        names.update(n for n, p in inspect.signature(fn).parameters.items()
                     if n != "self" and p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL))
    return sorted(names - {"model_path", "observation_space"})


def make_sand_env(gym_id: str, **kwargs) -> GranularWrapper:
    """``GranularWrapper(<gymnasium env gym_id>)``: the entry point of the registered sand variants
    (``mjrft.envs.GYM_SAND_IDS``). Keyword arguments named in :func:`wrapper_option_names` go to the wrapper
    (and the terrain), the others to the env (``frame_skip``, ``reset_noise_scale``, ``render_mode``, ...)."""
    spec, creator = _env_creator(gym_id)
    wrapper_names = set(wrapper_option_names())
    env_names = env_option_names(gym_id)
    wrapper_kw = {k: v for k, v in kwargs.items() if k in wrapper_names}
    env_kw = {k: v for k, v in kwargs.items() if k not in wrapper_names}
    for name in env_kw:
        if name not in env_names:
            raise unknown(f"keyword argument of {gym_id} on sand", name, sorted(wrapper_names | set(env_names)))
    env = creator(**{**spec.kwargs, **env_kw})
    try:
        return GranularWrapper(env, **wrapper_kw)
    except Exception:
        env.close()
        raise


make_sand_env.valid_kwargs = lambda gym_id, **_: sorted(set(wrapper_option_names()) | set(env_option_names(gym_id)))
