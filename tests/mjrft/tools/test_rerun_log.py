"""The rerun logger: the saved file, read back with rerun's dataframe API, holds what the simulation computed."""

from __future__ import annotations

import warnings

import mujoco
import numpy as np
import pytest

pytest.importorskip("rerun")
pytest.importorskip("datafusion")  # rerun's dataframe API (mjrft[rerun])
gymnasium = pytest.importorskip("gymnasium")

import mjrft.envs  # noqa: E402,F401
from mjrft.coupler import GranularTerrain  # noqa: E402
from mjrft.errors import TerrainStabilityWarning  # noqa: E402
from mjrft.tools.gaits import make_gait  # noqa: E402
from mjrft.models import hexapod_model  # noqa: E402
from mjrft.tools.rerun_log import RerunLogger, episode_logger, read_table, stress_colors  # noqa: E402


def _col(table, name):
    return table.column(name).to_pylist()


@pytest.fixture(scope="module")
def hexapod_run(tmp_path_factory):
    """Tripod gait on poppy seeds, 80 env steps, logged every 10th; snapshots of the terrain at each frame."""
    path = tmp_path_factory.mktemp("rrd") / "hexapod.rrd"
    env = gymnasium.make("mjrft/HexapodSand-v0", max_episode_steps=1000)
    u = env.unwrapped
    gait = make_gait("tripod:f=2", env)
    obs, _ = env.reset(seed=0)
    snaps = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        with episode_logger(path, env) as log:
            for k in range(80):
                action, _ = gait.predict(obs)
                obs, *_ = env.step(action)
                if (k + 1) % 10 == 0:
                    log.log(env)
                    t = u.terrain
                    snaps.append(dict(time=u.data.time, idx=np.flatnonzero(t.depth > 0), pos=t.pos.copy(),
                                      force=t.force.copy(), depth=t.depth.copy(), area=t.area.copy(),
                                      wrench=t.wrench.copy(), sink=t.sinkage(), xpos=u.data.xpos.copy(),
                                      elem_body=t.elem_body.copy()))
            frames = log.frames
            feet = log.plot_bodies.copy()
    env.close()
    return path, snaps, frames, feet, u


def test_contacts_and_forces_read_back_equal_the_simulation(hexapod_run):
    path, snaps, frames, feet, u = hexapod_run
    assert frames == len(snaps) == 8
    table = read_table(path, "/world/contacts")
    assert table.num_rows == len(snaps)
    times = [t.total_seconds() for t in _col(table, "sim_time")]
    np.testing.assert_allclose(times, [s["time"] for s in snaps], atol=1e-9)
    buried = 0
    for row, s in enumerate(snaps):
        idx = s["idx"]
        buried += len(idx)
        elem = _col(table, "/world/contacts:element")[row] or []
        np.testing.assert_array_equal(elem, idx)
        if not len(idx):
            continue
        pos = np.array(_col(table, "/world/contacts:Points3D:positions")[row])
        np.testing.assert_allclose(pos, s["pos"][idx], atol=1e-6)  # float32 positions
        for k, c in enumerate("xyz"):  # exact float64 force components
            np.testing.assert_array_equal(_col(table, f"/world/contacts:f{c}")[row], s["force"][idx, k])
        np.testing.assert_array_equal(_col(table, "/world/contacts:depth")[row], s["depth"][idx])
        np.testing.assert_array_equal(_col(table, "/world/contacts:body")[row], s["elem_body"][idx])
        stress = np.linalg.norm(s["force"][idx], axis=1) / s["area"][idx]
        np.testing.assert_allclose(_col(table, "/world/contacts:stress")[row], stress, rtol=1e-12)
        assert np.all(s["depth"][idx] > 0)
    assert buried > 50  # the legs were in the sand for most frames


def test_net_force_arrows_and_leg_series(hexapod_run):
    path, snaps, frames, feet, u = hexapod_run
    assert [u.model.body(int(b)).name for b in feet] == list(u.foot_names)
    plots = read_table(path, "/plots/**")
    for row, s in enumerate(snaps):
        lift = _col(plots, "/plots/lift:Scalars:scalars")[row]
        thrust = _col(plots, "/plots/thrust:Scalars:scalars")[row]
        sink = _col(plots, "/plots/sinkage:Scalars:scalars")[row]
        np.testing.assert_allclose(lift, s["wrench"][feet, 2], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(thrust, s["wrench"][feet, 0], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(sink, s["sink"][feet], rtol=1e-12, atol=1e-12)
    names = read_table(path, "/plots/lift", index=None)
    assert _col(names, "/plots/lift:SeriesLines:names")[0] == list(u.foot_names)
    net = read_table(path, "/world/forces/net")
    log_scale = RerunLogger(u.model, u.terrain, path.with_name("scale.rrd")).force_scale
    for row, s in enumerate(snaps):
        vec = np.array(_col(net, "/world/forces/net:Arrows3D:vectors")[row])
        np.testing.assert_allclose(vec, s["wrench"][u.terrain.body_ids, :3] * log_scale, rtol=1e-5, atol=1e-9)
    elems = read_table(path, "/world/forces/elements")
    s = snaps[-1]
    vec = np.array(_col(elems, "/world/forces/elements:Arrows3D:vectors")[-1])
    assert vec.shape == (len(s["idx"]), 3)


def test_robot_poses_and_static_shapes(hexapod_run):
    path, snaps, frames, feet, u = hexapod_run
    poses = read_table(path, "/world/robot/torso")
    tid = u.model.body("torso").id
    for row, s in enumerate(snaps):
        np.testing.assert_allclose(_col(poses, "/world/robot/torso:Transform3D:translation")[row][0], s["xpos"][tid],
                                   atol=1e-6)
    static = read_table(path, "/**", index=None)
    cols = static.column_names
    n_boxes = sum(c.endswith(":Boxes3D:half_sizes") and c.startswith("/world/robot/") for c in cols)
    robot_geoms = [g for g in range(u.model.ngeom) if u.model.geom_bodyid[g] > 0 and u.model.geom_group[g] < 3]
    assert n_boxes == len(robot_geoms)  # every robot geom of the hexapod is a box
    assert "/world/ground/sand_surface:Boxes3D:half_sizes" in cols  # the sand bed
    assert "/world:ViewCoordinates:xyz" in cols


def test_logger_on_plain_model_closes_on_error(tmp_path):
    model = hexapod_model()
    data = mujoco.MjData(model)
    terrain = GranularTerrain(model, resolution=0.03)
    path = tmp_path / "plain.rrd"
    with pytest.raises(RuntimeError, match="boom"):
        with RerunLogger(model, terrain, path, bodies=["leg_lf", "leg_rf"]) as log:
            for _ in range(3):
                terrain.step(data, 50)
                log.log(data)
            raise RuntimeError("boom")
    assert log._closed
    table = read_table(path, "/plots/sinkage")
    assert table.num_rows == 3
    last = _col(table, "/plots/sinkage:Scalars:scalars")[-1]
    np.testing.assert_allclose(last, terrain.sinkage()[[model.body("leg_lf").id, model.body("leg_rf").id]])
    with pytest.raises(RuntimeError, match="closed"):
        log.log(data)


def test_rigid_env_logs_poses_only(tmp_path):
    env = gymnasium.make("mjrft/BipedRigid-v0", max_episode_steps=5)
    env.reset(seed=0)
    with episode_logger(tmp_path / "rigid.rrd", env) as log:
        env.step(env.action_space.sample())
        log.log(env)
    table = read_table(tmp_path / "rigid.rrd", "/world/**")
    assert "/world/robot/torso:Transform3D:translation" in table.column_names
    assert not any(c.startswith("/world/contacts") for c in table.column_names)
    env.close()


def test_bad_arguments(tmp_path):
    model = hexapod_model()
    with pytest.raises(ValueError, match="spawn"):
        RerunLogger(model, None, None)
    with pytest.raises(ValueError, match="does not exist"):
        RerunLogger(model, None, tmp_path / "missing" / "x.rrd")
    with pytest.raises(ValueError, match="valid choices: .*leg_lf"):
        RerunLogger(model, None, tmp_path / "x.rrd", bodies=["leg_xx"])
    with pytest.raises(ValueError, match="force_scale"):
        RerunLogger(model, None, tmp_path / "x.rrd", force_scale=-1)
    with pytest.raises(TypeError, match="MjData"):
        with RerunLogger(model, None, tmp_path / "y.rrd") as log:
            log.log("not a simulation")
    with pytest.raises(FileNotFoundError):
        read_table(tmp_path / "nothing.rrd")


def test_stress_colors():
    c = stress_colors(np.array([0.0, 5.0, 10.0, 20.0]), 10.0)
    assert c.dtype == np.uint8 and c.shape == (4, 3)
    np.testing.assert_array_equal(c[0], [68, 1, 84])
    np.testing.assert_array_equal(c[2], [253, 231, 37])
    np.testing.assert_array_equal(c[3], c[2])  # clipped


def test_a_spawned_viewer_listens_on_this_machine_only_unless_asked(monkeypatch):
    from mjrft.tools import rerun_log

    started, listening = [], {"now": False}

    def popen(argv, **kwargs):
        started.append(argv)
        listening["now"] = True

    monkeypatch.setattr(rerun_log.subprocess, "Popen", popen)
    monkeypatch.setattr(rerun_log, "_listening", lambda host, port: listening["now"])
    url = rerun_log.spawn_viewer(port=9911)
    assert url == "rerun+http://127.0.0.1:9911/proxy"
    argv = started[-1]
    assert argv[argv.index("--bind") + 1] == "127.0.0.1" and argv[argv.index("--port") + 1] == "9911"
    assert rerun_log.spawn_viewer(port=9911) == url and len(started) == 1  # one already listens: reused
    listening["now"] = False
    assert rerun_log.spawn_viewer(port=9912, bind="0.0.0.0") == "rerun+http://127.0.0.1:9912/proxy"
    assert started[-1][started[-1].index("--bind") + 1] == "0.0.0.0"
