"""Log a MuJoCo simulation with granular terrain to rerun (``.rrd`` file, or a viewer on request).

>>> from mjrft.tools.rerun_log import RerunLogger
>>> with RerunLogger(model, terrain, "run.rrd") as log:      # headless: writes run.rrd
...     for _ in range(100):
...         terrain.step(data, 10)
...         log.log(data)                                   # one frame at data.time

Open the file with ``rerun run.rrd`` (or ``python -m rerun run.rrd``). ``spawn=True`` also streams
to a newly started viewer. For a gymnasium environment, :func:`episode_logger` builds the logger from
``env.unwrapped`` and ``log`` accepts the env itself.

Every logged frame is stamped on the ``sim_time`` timeline (simulation time, a duration) and the
``frame`` sequence. What is logged (entity paths):

=========================  ==============================================================================
``world``                  view coordinates: right handed, z up (static)
``world/ground/<geom>``    world-body geoms (the sand bed ``sand_surface`` box, floor / bed planes as
                           2 m squares), static
``world/sand``             the sand surface: a translucent square at ``terrain.surface`` (static; only
                           when the model has no ``sand_surface`` geom)
``world/robot/<body>``     the body's pose (``Transform3D``: ``xpos``, ``xmat``) every frame
``.../<body>/<geom>``      the geom's shape in its body (box, sphere, ellipsoid, capsule, cylinder, mesh),
                           its local pose and colour, static
``world/contacts``         the elements below the surface (``terrain.depth > 0``) as points at
                           ``terrain.pos``, coloured by stress ``|force| / area`` (dark blue -> yellow,
                           see ``stress_max``), radius ``sqrt(area) / 2``; the exact values ride along
                           as columns ``element`` (index into the terrain arrays), ``body``,
                           ``depth`` (m), ``area`` (m^2), ``stress`` (Pa), ``fx``, ``fy``, ``fz`` (N,
                           float64)
``world/forces/elements``  one arrow per contact element: ``force x element_force_scale`` (m/N)
``world/forces/net``       one arrow per granular body at its centre of mass: the net granular force
                           ``terrain.wrench[body, :3] x force_scale`` (m/N), labelled with the body name
``plots/lift``             per leg/foot body: vertical granular force (N, +z up) — one series per body
``plots/thrust``           per leg/foot body: forward granular force (N, world +x)
``plots/sinkage``          per leg/foot body: deepest element below the surface (m)
``world/ground_memory``    with a ground memory (``ground_memory=True``): the grains' surface over the part
                           of the grid that changed since the reset (its box and 2 cells around), a mesh
                           through the cell centres, coloured by packing (loosely packed dark brown ->
                           closely packed light sand; ``GROUND_COLORS``): footprints, ridges and the
                           sheared grains, every frame
``plots/ground``           with a ground memory: the lowest and highest surface (m, above the undisturbed
                           one) and the loosest volume fraction of the grid
=========================  ==============================================================================

Choices: the forces at a frame are those the terrain applied over the last physics step (computed
from the state at its start); the frame is stamped with ``data.time`` after that step. Geoms of
group 3 and above (MuJoCo's hidden groups) are not drawn. Arrow scales default to: a body carrying
the robot's whole weight gets a net-force arrow as long as the robot (its largest extent at the
initial pose); element arrows are 10 x longer per newton than net arrows. Stress colours run from 0
to ``stress_max`` (Pa); when it is None (default) the largest stress logged so far is used, so the
colour scale only grows and stays comparable once the robot has loaded the sand.

Speed: the static shapes are sent once; a frame costs one transform per body plus six small
records, so logging every 10th env step adds well under 2x to a rollout (``benchmarks/bench_logging.py``).
"""

from __future__ import annotations

import math
import os
import shutil
import socket
import subprocess
import sys
import time
import uuid

import mujoco
import numpy as np

G = 9.81
LOG_EVERY = 5  # env steps between logged frames: the default of mjrft demo, rollout and eval --rrd
#: colour map anchors (viridis-like) for stress, from 0 to stress_max
_CMAP = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], dtype=np.float64)
_SAND_RGBA = (219, 189, 133, 110)
#: the ground memory's colours (RGB) of loosely and of closely packed grains
GROUND_COLORS = ((120, 84, 45), (235, 210, 160))


#: the port a spawned viewer listens on (rerun's default)
VIEWER_PORT = 9876


def spawn_viewer(port: int = VIEWER_PORT, bind: str = "127.0.0.1", timeout: float = 15.0) -> str:
    """Start a rerun viewer that listens on ``bind``:``port``, unless one listens there already; return the
    URL to stream to. ``rerun.spawn`` would listen on every network interface; mjrft's default is this
    machine only (``bind="0.0.0.0"`` opens it to the network)."""
    host = "127.0.0.1" if bind in ("0.0.0.0", "::", "") else bind
    url_host = f"[{host}]" if ":" in host else host
    url = f"rerun+http://{url_host}:{int(port)}/proxy"
    if _listening(host, port):
        return url
    exe = shutil.which("rerun") or os.path.join(os.path.dirname(sys.executable), "rerun")
    if not os.path.isfile(exe):
        raise ValueError("the rerun viewer executable is not installed (pip install 'mjrft[rerun]')")
    subprocess.Popen([exe, "--port", str(int(port)), "--bind", bind], stdin=subprocess.DEVNULL,
                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
                     env={**os.environ, "RERUN_APP_ONLY": "true"})
    deadline = time.monotonic() + timeout
    while not _listening(host, port):
        if time.monotonic() > deadline:
            raise RuntimeError(f"the rerun viewer did not start listening on {bind}:{port} within {timeout:g} s")
        time.sleep(0.05)
    return url


def _listening(host: str, port: int) -> bool:
    try:
        with socket.create_connection((host, int(port)), timeout=0.2):
            return True
    except OSError:
        return False


def stress_colors(stress: np.ndarray, vmax: float) -> np.ndarray:
    """RGB uint8 colours (n, 3) for ``stress / vmax`` in [0, 1] (clipped) on a viridis-like map."""
    s = np.clip(np.asarray(stress, dtype=np.float64) / (vmax if vmax > 0 else 1.0), 0.0, 1.0)
    x = s * (len(_CMAP) - 1)
    i = np.minimum(x.astype(np.int64), len(_CMAP) - 2)
    f = (x - i)[:, None]
    return np.round(_CMAP[i] * (1.0 - f) + _CMAP[i + 1] * f).astype(np.uint8)


def _name(model, kind, i: int, prefix: str) -> str:
    n = mujoco.mj_id2name(model, kind, i)
    return n if n else f"{prefix}{i}"


def _safe(name: str) -> str:
    """An entity-path part: letters, digits, '_', '-', '.'; anything else becomes '-'."""
    return "".join(c if (c.isalnum() or c in "_-.") else "-" for c in name)


def _geom_rgba(model, g: int) -> tuple[int, int, int, int]:
    rgba = model.geom_rgba[g]
    if model.geom_matid[g] >= 0:
        rgba = model.mat_rgba[model.geom_matid[g]]
    return tuple(int(round(255 * float(np.clip(c, 0.0, 1.0)))) for c in rgba)


def geom_archetype(model, g: int, rr):
    """The rerun archetype drawing geom ``g`` in its own frame, or None for unsupported types."""
    t = model.geom_type[g]
    size = model.geom_size[g]
    color = [_geom_rgba(model, g)]
    T = mujoco.mjtGeom
    if t == T.mjGEOM_BOX:
        return rr.Boxes3D(half_sizes=[size], colors=color, fill_mode="solid")
    if t == T.mjGEOM_SPHERE:
        return rr.Ellipsoids3D(half_sizes=[[size[0]] * 3], colors=color, fill_mode="solid")
    if t == T.mjGEOM_ELLIPSOID:
        return rr.Ellipsoids3D(half_sizes=[size], colors=color, fill_mode="solid")
    if t == T.mjGEOM_CAPSULE:  # MuJoCo: centred on the origin along z; rerun: from the origin to +length
        return rr.Capsules3D(lengths=[2 * size[1]], radii=[size[0]], translations=[[0, 0, -size[1]]],
                             colors=color, fill_mode="solid")
    if t == T.mjGEOM_CYLINDER:
        return rr.Cylinders3D(lengths=[2 * size[1]], radii=[size[0]], colors=color, fill_mode="solid")
    if t == T.mjGEOM_MESH:
        m = model.geom_dataid[g]
        va, nv = model.mesh_vertadr[m], model.mesh_vertnum[m]
        fa, nf = model.mesh_faceadr[m], model.mesh_facenum[m]
        return rr.Mesh3D(vertex_positions=model.mesh_vert[va:va + nv], triangle_indices=model.mesh_face[fa:fa + nf],
                         albedo_factor=color[0])
    if t == T.mjGEOM_PLANE:
        hx = size[0] if size[0] > 0 else 1.0
        hy = size[1] if size[1] > 0 else 1.0
        return rr.Mesh3D(vertex_positions=[[-hx, -hy, 0], [hx, -hy, 0], [hx, hy, 0], [-hx, hy, 0]],
                         triangle_indices=[[0, 1, 2], [0, 2, 3]], albedo_factor=color[0])
    return None


def _unwrap(source):
    """(model, data, env or None) from an MjData, a gymnasium env (wrapped or not) or an object with .data."""
    if isinstance(source, mujoco.MjData):
        return None, source, None
    env = getattr(source, "unwrapped", source)
    data = getattr(env, "data", None)
    if not isinstance(data, mujoco.MjData):
        raise TypeError(f"log() needs a mujoco.MjData or a MuJoCo gymnasium env, got {type(source).__name__}")
    return env.model, data, env


class RerunLogger:
    """Rerun logger of one simulation (see the module docstring for what it records).

    Args:
        model: the ``MjModel``.
        terrain: the :class:`mjrft.GranularTerrain` (None: robot poses only, e.g. rigid ground).
        path: ``.rrd`` file to write (None: no file; then ``spawn`` must be True).
        spawn: also start a rerun viewer and stream to it (:func:`spawn_viewer`).
        viewer_bind: the address the spawned viewer listens on (default ``127.0.0.1``: this machine only;
            ``0.0.0.0`` lets any machine on the network connect to it).
        name: application id shown in the viewer.
        bodies: body names for the per-leg plots (default: every granular body of the terrain).
        force_scale: m per N of the net-force arrows (default: robot extent / weight).
        element_force_scale: m per N of the element arrows (default: 10 x force_scale).
        stress_max: Pa at the top of the colour scale (default: running maximum).
        recording_id: rerun recording id (default: a fresh uuid).
    """

    def __init__(self, model: mujoco.MjModel, terrain=None, path=None, *, spawn: bool = False, name: str = "mjrft",
                 bodies=None, force_scale: float | None = None, element_force_scale: float | None = None,
                 stress_max: float | None = None, recording_id: str | None = None, viewer_bind: str = "127.0.0.1"):
        try:
            import rerun as rr
        except ImportError:  # pragma: no cover - rerun is an optional extra
            raise ImportError("rerun logging needs the rerun extra: pip install 'mjrft[rerun]'") from None
        from mjrft.errors import check_positive, unknown

        if not isinstance(model, mujoco.MjModel):
            raise TypeError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        if path is None and not spawn:
            raise ValueError("RerunLogger needs a path to write (.rrd) or spawn=True for a viewer")
        if spawn:
            check_viewer_display()
        self._rr = rr
        self.model = model
        self.terrain = terrain
        self.path = None if path is None else os.fspath(path)
        self.frames = 0
        self._closed = False
        self.stress_max = None if stress_max is None else check_positive("stress_max", stress_max)
        self._stress_seen = 0.0

        names = {_name(model, mujoco.mjtObj.mjOBJ_BODY, b, "body"): b for b in range(model.nbody)}
        if bodies is None:
            ids = [] if terrain is None else [int(b) for b in terrain.body_ids]
        else:
            ids = []
            for b in bodies:
                if isinstance(b, str):
                    if b not in names:
                        raise unknown("body", b, [n for n in names if names[n] > 0])
                    ids.append(names[b])
                else:
                    ids.append(int(b))
        self.plot_bodies = np.array(ids, dtype=np.int64)
        self._plot_names = [_name(model, mujoco.mjtObj.mjOBJ_BODY, b, "body") for b in self.plot_bodies]

        # robot size and weight for the default arrow scales
        d0 = mujoco.MjData(model)
        mujoco.mj_forward(model, d0)
        robot_geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] > 0]
        weight = float(model.body_subtreemass[0]) * G
        if robot_geoms:
            com = d0.subtree_com[0]
            extent = max(float(np.linalg.norm(d0.geom_xpos[g] - com) + model.geom_rbound[g]) for g in robot_geoms)
        else:
            extent = 1.0
        self.force_scale = (check_positive("force_scale", force_scale) if force_scale is not None
                            else extent / max(weight, 1e-9))
        self.element_force_scale = (check_positive("element_force_scale", element_force_scale)
                                    if element_force_scale is not None else 10.0 * self.force_scale)

        # rerun application ids are entry names: letters, digits, '-' and '_'
        app_id = "".join(c if (c.isalnum() or c in "_-") else "-" for c in str(name)) or "mjrft"
        self.rec = rr.RecordingStream(app_id, recording_id=recording_id or str(uuid.uuid4()))
        try:
            sinks = []
            if self.path is not None:
                parent = os.path.dirname(os.path.abspath(self.path))
                if not os.path.isdir(parent):
                    raise ValueError(f"cannot write {self.path!r}: folder {parent!r} does not exist")
                sinks.append(rr.FileSink(self.path))
            if spawn:
                sinks.append(rr.GrpcSink(spawn_viewer(bind=viewer_bind)))
            self.rec.set_sinks(*sinks)
            self._log_static()
        except BaseException:
            self.close()
            raise

    # ------------------------------------------------------------------ static content
    def _log_static(self) -> None:
        rr, m, rec = self._rr, self.model, self.rec
        rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        self._body_paths = {}
        has_sand_geom = False
        for g in range(m.ngeom):
            if m.geom_group[g] >= 3:
                continue
            arche = geom_archetype(m, g, rr)
            if arche is None:
                continue
            gname = _safe(_name(m, mujoco.mjtObj.mjOBJ_GEOM, g, "geom"))
            b = int(m.geom_bodyid[g])
            if b == 0:
                has_sand_geom |= gname == "sand_surface"
                path = f"world/ground/{gname}"
            else:
                if b not in self._body_paths:
                    self._body_paths[b] = "world/robot/" + _safe(_name(m, mujoco.mjtObj.mjOBJ_BODY, b, "body"))
                path = f"{self._body_paths[b]}/{gname}"
            q = m.geom_quat[g]
            rec.log(path, rr.Transform3D(translation=m.geom_pos[g], quaternion=[q[1], q[2], q[3], q[0]]), static=True)
            rec.log(path, arche, static=True)
        self._bodies = np.array(sorted(self._body_paths), dtype=np.int64)
        if self.terrain is not None and not has_sand_geom:
            z = float(self.terrain.surface)
            rec.log("world/sand", rr.Mesh3D(vertex_positions=[[-1, -1, z], [1, -1, z], [1, 1, z], [-1, 1, z]],
                                             triangle_indices=[[0, 1, 2], [0, 2, 3]], albedo_factor=_SAND_RGBA),
                    static=True)
        if len(self.plot_bodies):
            for what in ("lift", "thrust", "sinkage"):
                rec.log(f"plots/{what}", rr.SeriesLines(names=self._plot_names), static=True)
        if self.terrain is not None and getattr(self.terrain, "ground_memory", False):
            rec.log("plots/ground", rr.SeriesLines(names=["lowest surface (m)", "highest surface (m)",
                                                          "loosest volume fraction"]), static=True)

    # ------------------------------------------------------------------ per frame
    def log(self, source) -> None:
        """Log one frame from ``source``: an ``MjData`` or a MuJoCo gymnasium env (wrapped or not)."""
        if self._closed:
            raise RuntimeError("this RerunLogger is closed")
        model, data, _ = _unwrap(source)
        if model is not None and model is not self.model:
            raise ValueError("log() got a simulation of a different model than the logger was made for")
        rr, rec = self._rr, self.rec
        rec.set_time("sim_time", duration=float(data.time))
        rec.set_time("frame", sequence=self.frames)
        for b in self._bodies:
            rec.log(self._body_paths[b], rr.Transform3D(translation=data.xpos[b], mat3x3=data.xmat[b].reshape(3, 3)))
        t = self.terrain
        if t is not None:
            mask = t.depth > 0.0
            idx = np.flatnonzero(mask)
            pos = t.pos[idx]
            force = t.force[idx]
            area = t.area[idx]
            stress = np.linalg.norm(force, axis=1) / area
            if len(stress):
                self._stress_seen = max(self._stress_seen, float(stress.max()))
            vmax = self.stress_max if self.stress_max is not None else self._stress_seen
            points = rr.Points3D(pos, colors=stress_colors(stress, vmax), radii=0.5 * np.sqrt(area))
            if len(idx):
                rec.log("world/contacts", points,
                        rr.AnyValues(element=idx, body=t.elem_body[idx], depth=t.depth[idx], area=area,
                                     stress=stress, fx=force[:, 0], fy=force[:, 1], fz=force[:, 2]))
            else:  # nothing buried: an empty point cloud (rerun drops empty untyped value columns)
                rec.log("world/contacts", points)
            rec.log("world/forces/elements", rr.Arrows3D(origins=pos, vectors=force * self.element_force_scale,
                                                         colors=[(230, 80, 40)]))
            bodies = t.body_ids
            rec.log("world/forces/net", rr.Arrows3D(origins=data.xipos[bodies],
                                                    vectors=t.wrench[bodies, :3] * self.force_scale,
                                                    colors=[(200, 30, 30)],
                                                    labels=[_name(self.model, mujoco.mjtObj.mjOBJ_BODY, int(b), "body")
                                                            for b in bodies]))
            if t.ground_memory:
                self._log_ground(t)
            if len(self.plot_bodies):
                w = t.wrench[self.plot_bodies]
                rec.log("plots/lift", rr.Scalars(w[:, 2]))
                rec.log("plots/thrust", rr.Scalars(w[:, 0]))
                rec.log("plots/sinkage", rr.Scalars(t.sinkage()[self.plot_bodies]))
        self.frames += 1

    def _log_ground(self, t) -> None:
        """The ground memory's surface over the part of the grid that changed (module docstring)."""
        rr, rec = self._rr, self.rec
        gt, st = t.terrain_model.ground, t.terrain_state
        h, phi = st.g_height, st.g_phi
        changed = (np.abs(h) > 1e-6) | (np.abs(phi - gt.pack[3]) > 1e-6)
        rec.log("plots/ground", rr.Scalars([float(h.min()), float(h.max()), float(phi.min())]))
        rows, cols = np.nonzero(changed.any(axis=1))[0], np.nonzero(changed.any(axis=0))[0]
        if not len(rows):
            rec.log("world/ground_memory", rr.Clear(recursive=False))
            return
        ny, nx = h.shape
        j0, j1 = max(0, rows[0] - 2), min(ny, rows[-1] + 3)
        i0, i1 = max(0, cols[0] - 2), min(nx, cols[-1] + 3)
        x0, y0, c = gt.frame[0], gt.frame[1], gt.frame[2]
        xs = x0 + (np.arange(i0, i1) + 0.5) * c
        ys = y0 + (np.arange(j0, j1) + 0.5) * c
        gx, gy = np.meshgrid(xs, ys)
        z = gt.base[j0:j1, i0:i1] + h[j0:j1, i0:i1]
        verts = np.stack([gx.ravel(), gy.ravel(), z.ravel()], axis=1)
        m, n = j1 - j0, i1 - i0
        k = (np.arange(m - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
        tris = np.concatenate([np.stack([k, k + 1, k + n + 1], 1), np.stack([k, k + n + 1, k + n], 1)])
        s = np.clip((phi[j0:j1, i0:i1].ravel() - gt.pack[0]) * gt.pack[4], 0.0, 1.0) if gt.pack[4] > 0 else \
            np.ones(verts.shape[0])
        lo, hi = np.array(GROUND_COLORS[0], float), np.array(GROUND_COLORS[1], float)
        colors = (lo + s[:, None] * (hi - lo)).astype(np.uint8)
        rec.log("world/ground_memory", rr.Mesh3D(vertex_positions=verts, triangle_indices=tris, vertex_colors=colors))

    # ------------------------------------------------------------------ lifetime
    def flush(self) -> None:
        if not self._closed:
            self.rec.flush()

    def close(self) -> None:
        """Flush everything to the file / viewer and close the stream (idempotent)."""
        if self._closed:
            return
        self._closed = True
        try:
            self.rec.flush()
        finally:
            self.rec.disconnect()

    def __enter__(self) -> "RerunLogger":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):  # a logger dropped without close() still leaves a complete file
        try:
            self.close()
        except Exception:
            pass


def check_viewer_display() -> None:
    """Raise ``ValueError`` when a spawned viewer could not open a window (Linux or BSD without a display).

    The rerun viewer is a desktop program: with no X11 or Wayland display it cannot start, and a
    spawned one would hang the caller. Commands call this before any work (``--spawn-viewer``).
    """
    import sys

    if sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")) and not (
            os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise ValueError("--spawn-viewer needs a display (neither DISPLAY nor WAYLAND_DISPLAY is set); drop it "
                         "and open the written file later with: rerun FILE")


def episode_logger(path, env, *, name: str | None = None, spawn: bool = False, **kwargs) -> RerunLogger:
    """A :class:`RerunLogger` for a mjrft gymnasium env: its model, terrain and feet/legs (``foot_names``)."""
    u = getattr(env, "unwrapped", env)
    model = getattr(u, "model", None)
    if not isinstance(model, mujoco.MjModel):
        raise TypeError(f"episode_logger needs a MuJoCo gymnasium env, got {type(u).__name__}")
    terrain = getattr(u, "terrain", None)
    feet = getattr(u, "foot_names", None)
    if terrain is not None and feet and "bodies" not in kwargs:
        kwargs["bodies"] = list(feet)
    env_id = getattr(getattr(env, "spec", None), "id", None) or type(u).__name__
    return RerunLogger(model, terrain, path, spawn=spawn, name=name or f"mjrft-{env_id}", **kwargs)


def read_table(path, contents: str = "/**", index: str = "sim_time"):
    """Read ``contents`` of a saved ``.rrd`` back as a ``pyarrow.Table`` (rerun's dataframe API).

    Columns are named ``"<entity>:<component>"`` (e.g. ``/world/contacts:Points3D:positions``,
    ``/world/contacts:stress``), one row per logged frame, plus the index column. Needs the
    ``datafusion`` package (``pip install 'mjrft[rerun]'``).
    """
    from rerun.chunk import RrdReader

    if not os.path.isfile(path):
        raise FileNotFoundError(f"no rerun file at {os.fspath(path)!r}")
    store = RrdReader(os.fspath(path)).store().stream().collect()
    table = store.reader(index=index, contents=contents).to_arrow_table()
    if index in table.column_names:
        table = table.sort_by(index)
    return table


__all__ = ["RerunLogger", "episode_logger", "geom_archetype", "read_table", "stress_colors"]
