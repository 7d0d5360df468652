"""The rerun logger with a ground memory: the recorded surface mesh is the ground the terrain holds (footprints,
ridges, packing), frame by frame; without a memory nothing of it is recorded (the control)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

pytest.importorskip("rerun")
pytest.importorskip("datafusion")  # rerun's dataframe API (mjrft[rerun])
gymnasium = pytest.importorskip("gymnasium")

import mjrft.envs  # noqa: E402,F401
from mjrft.tools.gaits import make_gait  # noqa: E402
from mjrft.tools.rerun_log import GROUND_COLORS, episode_logger, read_table  # noqa: E402


def _walk(path, memory: bool):
    """30 env steps of the tripod on poppy seeds, logged every 10th; the ground's (height, packing) at each frame."""
    env = gymnasium.make("mjrft/HexapodSand-v0", max_episode_steps=1000, ground_memory=memory)
    u = env.unwrapped
    gait = make_gait("tripod:f=2", env)
    obs, _ = env.reset(seed=0)
    snaps = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with episode_logger(path, env) as log:
            for k in range(30):
                action, _ = gait.predict(obs)
                obs, *_ = env.step(action)
                if (k + 1) % 10 == 0:
                    log.log(env)
                    st = u.terrain.terrain_state
                    snaps.append((st.g_height.copy(), st.g_phi.copy()) if memory else None)
    gt = u.terrain.terrain_model.ground
    env.close()
    return snaps, gt


def test_the_ground_mesh_is_the_terrains_ground(tmp_path):
    snaps, gt = _walk(tmp_path / "ground.rrd", True)
    table = read_table(tmp_path / "ground.rrd", "/world/ground_memory")
    assert table.num_rows == len(snaps) == 3
    verts = table.column("/world/ground_memory:Mesh3D:vertex_positions").to_pylist()
    colors = table.column("/world/ground_memory:Mesh3D:vertex_colors").to_pylist()
    x0, y0, c = gt.frame[0], gt.frame[1], gt.frame[2]
    deepest = 0.0
    for row, (h, phi) in enumerate(snaps):
        v = np.array(verts[row])
        i = np.rint((v[:, 0] - x0) / c - 0.5).astype(int)
        j = np.rint((v[:, 1] - y0) / c - 0.5).astype(int)
        np.testing.assert_allclose(v[:, 2], gt.base[j, i] + h[j, i], atol=1e-6)  # float32 positions
        assert np.abs(h).max() == pytest.approx(max(np.abs(v[:, 2] - gt.base[j, i]).max(), 0.0), abs=1e-6)
        col = np.array(colors[row], dtype=np.uint32)
        rgb = np.stack([(col >> 24) & 255, (col >> 16) & 255, (col >> 8) & 255], 1).astype(float)
        lo, hi = np.array(GROUND_COLORS[0]), np.array(GROUND_COLORS[1])
        s = np.clip((phi[j, i] - gt.pack[0]) * gt.pack[4], 0, 1)
        np.testing.assert_allclose(rgb, lo + s[:, None] * (hi - lo), atol=1.0)
        deepest = min(deepest, h.min())
    assert deepest < -1e-3  # footprints were recorded


def test_no_ground_memory_records_no_ground(tmp_path):
    _walk(tmp_path / "plain.rrd", False)
    cols = read_table(tmp_path / "plain.rrd", "/**", index=None).column_names
    assert not any("ground_memory" in c or c.startswith("/plots/ground") for c in cols)
