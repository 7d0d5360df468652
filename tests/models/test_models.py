"""Robot / scene models (mjrft.models) and the curved-leg geometry helper."""

from __future__ import annotations

import math
import os

import mujoco
import numpy as np
import pytest

from mjrft.geometry.curved_leg import (
    add_curved_leg,
    arc_length,
    arc_points,
    curved_leg_boxes,
    curved_leg_xml,
)
from mjrft.models import MODEL_NAMES, model_path
from mjrft.models.biped import biped_model, biped_xml
from mjrft.models.generate import generated
from mjrft.models.hexapod import LEG_NAMES, hexapod_model, hexapod_xml, pitch_inertia
from mjrft.models.humanoid import humanoid_model

RP = 0.0205  # R' of the RHex-class leg (m)
N_STEPS = 1000


# ----------------------------------------------------------------- helpers


def _rollout(m: mujoco.MjModel, n: int = N_STEPS) -> mujoco.MjData:
    d = mujoco.MjData(m)
    for _ in range(n):
        mujoco.mj_step(m, d)
    assert np.all(np.isfinite(d.qpos)) and np.all(np.isfinite(d.qvel)), "NaN/inf in state"
    return d


def _z_extent(m: mujoco.MjModel, d: mujoco.MjData | None = None) -> tuple[float, float]:
    """(lowest, highest) world z of the robot's geoms (at qpos0 unless ``d`` is given)."""
    d = mujoco.MjData(m) if d is None else d
    mujoco.mj_forward(m, d)
    signs = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1).T
    lo, hi = np.inf, -np.inf
    for g in range(m.ngeom):
        if m.geom_bodyid[g] == 0:
            continue
        c, h = m.geom_aabb[g, :3], m.geom_aabb[g, 3:]
        R = d.geom_xmat[g].reshape(3, 3)
        z = (d.geom_xpos[g] + (c + signs * h) @ R.T)[:, 2]
        lo, hi = min(lo, z.min()), max(hi, z.max())
    return lo, hi


def _robot_mass(m: mujoco.MjModel) -> float:
    return float(m.body_mass[1:].sum())


def _custom(m: mujoco.MjModel) -> tuple[dict, dict]:
    texts, nums = {}, {}
    for i in range(m.ntext):
        raw = bytes(m.text_data[m.text_adr[i] : m.text_adr[i] + m.text_size[i]])
        texts[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_TEXT, i)] = raw.split(b"\0")[0].decode()
    for i in range(m.nnumeric):
        nums[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_NUMERIC, i)] = np.array(
            m.numeric_data[m.numeric_adr[i] : m.numeric_adr[i] + m.numeric_size[i]]
        )
    return texts, nums


def _assert_sand_scene(m: mujoco.MjModel, resolution: float) -> None:
    texts, nums = _custom(m)
    assert texts["mjrft:medium"] == "poppy_cp"
    assert texts["mjrft:law"] == "rft"
    bodies = texts["mjrft:bodies"].split()
    assert bodies
    for b in bodies:
        assert mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, b) >= 0, b
    assert nums["mjrft:surface"][0] == 0.0
    assert nums["mjrft:resolution"][0] == pytest.approx(resolution)
    sand = m.geom("sand_surface")
    assert sand.contype[0] == 0 and sand.conaffinity[0] == 0
    assert sand.pos[2] + sand.size[2] <= 1e-12  # surface box at z <= 0
    bottom = m.geom("bed_bottom")
    assert bottom.type[0] == mujoco.mjtGeom.mjGEOM_PLANE
    assert bottom.pos[2] == pytest.approx(-0.3)
    assert bottom.conaffinity[0] == 1
    with pytest.raises(KeyError):
        m.geom("floor")


def _assert_rigid_scene(m: mujoco.MjModel) -> None:
    floor = m.geom("floor")
    assert floor.type[0] == mujoco.mjtGeom.mjGEOM_PLANE and floor.pos[2] == 0.0
    assert floor.conaffinity[0] == 1
    texts, _ = _custom(m)
    assert "mjrft:bodies" not in texts


def _assert_common(m: mujoco.MjModel) -> None:
    assert m.opt.timestep == pytest.approx(0.001)
    assert m.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert int(m.camera("track").mode[0]) in (
        int(mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM), int(mujoco.mjtCamLight.mjCAMLIGHT_TRACK))
    assert m.nlight >= 1
    # every actuator is a torque-limited position servo named after its joint
    for a in range(m.nu):
        act = m.actuator(a)
        assert m.joint(act.trnid[0]).name == act.name
        assert act.forcelimited[0] and act.forcerange[0] < 0 < act.forcerange[1]
        assert act.biastype[0] == mujoco.mjtBias.mjBIAS_AFFINE and act.gainprm[0] > 0


# ----------------------------------------------------------------- curved leg


@pytest.mark.parametrize("k", [-1 / RP, -0.92 / RP, -0.6 / RP, 0.0, 0.6 / RP, 0.92 / RP, 1 / RP])
def test_curved_leg_boxes_follow_arc(k):
    chord, width, t, n = 0.041, 0.01, 0.003, 8
    boxes = curved_leg_boxes(chord, k, width, t, n)
    assert len(boxes) == n
    pts = arc_points(chord, k, n)
    np.testing.assert_allclose(pts[0], 0, atol=1e-12)
    np.testing.assert_allclose(pts[-1], [0, 0, -chord], atol=1e-12)
    r = math.inf if k == 0 else 1 / abs(k)
    for i, b in enumerate(boxes):
        assert b["size"][0] == pytest.approx(t / 2) and b["size"][1] == pytest.approx(width / 2)
        assert b["pos"][1] == 0.0 and np.linalg.norm(b["quat"]) == pytest.approx(1)
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, np.asarray(b["quat"], float))
        axis = R.reshape(3, 3)[:, 2]
        seg = pts[i + 1] - pts[i]
        # box long axis is the segment chord, box covers at least the chord
        assert abs(abs(axis @ seg) - np.linalg.norm(seg)) < 1e-9
        assert 2 * b["size"][2] >= np.linalg.norm(seg) - 1e-12
        np.testing.assert_allclose(np.cross(axis, seg), 0, atol=1e-12)
        if k != 0:
            # chord length of an arc piece of the right length
            ds = arc_length(chord, k) / n
            assert np.linalg.norm(seg) == pytest.approx(2 * r * math.sin(ds / (2 * r)))
    # first box starts at the hip, last box ends at the tip
    for b, end in ((boxes[0], np.zeros(3)), (boxes[-1], np.array([0, 0, -chord]))):
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, np.asarray(b["quat"], float))
        ends = [b["pos"] + s * b["size"][2] * R.reshape(3, 3)[:, 2] for s in (-1, 1)]
        assert min(np.linalg.norm(e - end) for e in ends) < 1e-9
    # bow direction (mjrft.geometry.curved_leg): k > 0, the C-leg, bows toward -x, where the buried part
    # of a leg turning the forward-walking way (tip swung toward -x) moves: its convex side leads
    xmid = np.mean([b["pos"][0] for b in boxes])
    assert np.sign(xmid) == -np.sign(k) if k != 0 else abs(xmid) < 1e-12


def test_arc_length():
    assert arc_length(0.041, 0.0) == pytest.approx(0.041)
    assert arc_length(0.041, 1 / RP) == pytest.approx(math.pi * RP)
    assert arc_length(0.041, -1 / RP) == pytest.approx(math.pi * RP)
    assert 0.041 < arc_length(0.041, 0.6 / RP) < math.pi * RP


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(chord=0.0), "chord"),
        (dict(chord=-1.0), "chord"),
        (dict(chord=float("nan")), "chord"),
        (dict(width=0.0), "width"),
        (dict(thickness=float("inf")), "thickness"),
        (dict(n_segments=0), "n_segments"),
        (dict(curvature=1.01 / RP), "curvature"),
        (dict(curvature=-60.0), "-60"),
        (dict(curvature=float("nan")), "curvature"),
    ],
)
def test_curved_leg_invalid(kwargs, match):
    args = dict(chord=0.041, curvature=0.0, width=0.01, thickness=0.003, n_segments=4)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        curved_leg_boxes(**args)


def test_curved_leg_xml_and_spec_agree():
    xml = curved_leg_xml(0.041, 1 / RP, 0.01, 0.003, 6, name_prefix="c", rgba=(1, 0, 0, 1))
    assert xml.count("<geom") == 6 and 'name="c_seg5"' in xml
    m1 = mujoco.MjModel.from_xml_string(f"<mujoco><worldbody><body>{xml}</body></worldbody></mujoco>")
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body()
    geoms = add_curved_leg(body, 0.041, 1 / RP, 0.01, 0.003, 6, name_prefix="c", rgba=[1, 0, 0, 1])
    assert len(geoms) == 6
    m2 = spec.compile()
    np.testing.assert_allclose(m1.geom_pos, m2.geom_pos, atol=1e-8)
    np.testing.assert_allclose(m1.geom_size, m2.geom_size, atol=1e-8)
    np.testing.assert_allclose(np.abs(m1.geom_quat), np.abs(m2.geom_quat), atol=1e-8)


# ----------------------------------------------------------------- committed files


def test_model_path():
    for name in MODEL_NAMES:
        assert os.path.isfile(model_path(name))
    assert model_path("hexapod.xml") == model_path("hexapod")
    with pytest.raises(ValueError, match="hexapod_small"):
        model_path("nope")


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_committed_model_loads_and_is_current(name):
    with open(model_path(name)) as f:
        assert f.read() == generated(name), "stale: run python -m mjrft.models.generate"
    m = mujoco.MjModel.from_xml_path(model_path(name))
    _assert_common(m)
    if name.endswith("rigid"):
        _assert_rigid_scene(m)
    _rollout(m)


# ----------------------------------------------------------------- hexapod


@pytest.mark.parametrize("sand", [True, False])
@pytest.mark.parametrize("variant, rp", [("rhex", RP), ("small", 0.01)])
@pytest.mark.parametrize("kfrac", [-1.0, 0.0, 1.0])
def test_hexapod_variants(variant, rp, kfrac, sand):
    m = hexapod_model(kfrac / rp, variant=variant, sand=sand)
    mass = {"rhex": 0.150, "small": 0.025}[variant]
    assert _robot_mass(m) == pytest.approx(mass, rel=0.02)
    _assert_common(m)
    assert m.nu == 6 and m.body("torso").jntnum[0] == 1
    assert m.joint(m.body("torso").jntadr[0]).type[0] == mujoco.mjtJoint.mjJNT_FREE
    for n in LEG_NAMES:
        j = m.joint(f"hip_{n}")
        assert j.type[0] == mujoco.mjtJoint.mjJNT_HINGE
        np.testing.assert_allclose(j.axis, [0, 1, 0])
        assert m.body(j.bodyid[0]).name == f"leg_{n}"
    lo, hi = _z_extent(m)
    assert 0 <= lo < 1e-3  # lowest leg point just above z = 0
    if sand:
        _assert_sand_scene(m, 0.005)
        bodies = _custom(m)[0]["mjrft:bodies"].split()
        assert set(bodies) == {"torso"} | {f"leg_{n}" for n in LEG_NAMES}
    else:
        _assert_rigid_scene(m)
    _rollout(m)


def test_hexapod_geometry_and_inertia():
    m = hexapod_model(sand=False)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    # pitch inertia 2.08e3 g cm^2 about the CoM
    assert pitch_inertia(m, d) == pytest.approx(2.08e-4, rel=0.01)
    # torso 13 cm long; legs hang down with tips ~4.1 cm below the hips
    assert 2 * m.geom("torso").size[0] == pytest.approx(0.13)
    hip = d.xpos[m.body("leg_lf").id]
    assert hip[2] == pytest.approx(0.041, abs=2e-3)
    # tripods: front/rear of one side with the middle of the other
    assert d.xpos[m.body("leg_lf").id][0] > 0 > d.xpos[m.body("leg_lr").id][0]
    assert d.xpos[m.body("leg_lf").id][1] > 0 > d.xpos[m.body("leg_rm").id][1]
    texts, _ = _custom(m)
    assert texts["robot:tripod_a"].split() == ["leg_lf", "leg_rm", "leg_lr"]
    assert texts["robot:tripod_b"].split() == ["leg_rf", "leg_lm", "leg_rr"]


@pytest.mark.parametrize("kfrac", [1.0, 0.6, -0.6, -1.0])
def test_hexapod_leg_curvature_convention(kfrac):
    """Positive curvature is Li 2013's C-leg: turning the forward-walking way (positive hip angle, the
    buried part sweeping backward) its middle, the part farthest from the hip-tip chord, bulges toward
    where it moves, so the convex side leads; a negative curvature (reversed C-leg) leads with the
    concave side."""
    m = hexapod_model(kfrac / RP, sand=False)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    body = m.body("leg_lf").id
    hip = d.xpos[body].copy()
    ids = [g for g in range(m.ngeom) if m.geom_bodyid[g] == body]
    mid = ids[len(ids) // 2 - 1: len(ids) // 2 + 1]  # the two middle boxes of the chain
    bulge = d.geom_xpos[mid].mean(0) - hip  # from the chord (the hip's vertical) to the middle of the arc
    before = d.geom_xpos[mid].mean(0).copy()
    d.qpos[m.joint("hip_lf").qposadr[0]] += 1e-3
    mujoco.mj_forward(m, d)
    motion = d.geom_xpos[mid].mean(0) - before
    assert motion[0] < 0 and abs(motion[2]) < abs(motion[0])  # the hanging leg's middle moves backward
    assert np.sign(bulge[0] * motion[0]) == np.sign(kfrac)  # C-leg: bulge toward the motion
    assert float(_custom(m)[1]["robot:curvature"][0]) == pytest.approx(kfrac / RP)


def test_hexapod_servo_can_hold_body():
    """Tripod stance on the rigid floor keeps the body up; servos track a slow rotation."""
    m = hexapod_model(sand=False)
    d = mujoco.MjData(m)
    for _ in range(500):
        mujoco.mj_step(m, d)
    # still standing on the legs: within 3 mm of the start height (belly 2.3 cm up; on the belly the torso's
    # centre would be half its 3.7 cm height up)
    assert d.qpos[2] > m.body("torso").pos[2] - 0.003
    ids = [m.actuator(f"hip_{n}").id for n in LEG_NAMES]
    for _ in range(500):
        d.ctrl[ids] = 2.0 * d.time
        mujoco.mj_step(m, d)
    assert np.all(np.abs(d.qpos[7:] - d.ctrl) < 0.3)


def test_hexapod_invalid():
    with pytest.raises(ValueError, match="48.78"):
        hexapod_xml(60.0)
    with pytest.raises(ValueError, match="variant"):
        hexapod_xml(variant="huge")
    with pytest.raises(TypeError, match="bogus"):
        hexapod_xml(bogus=1)


# ----------------------------------------------------------------- biped


@pytest.mark.parametrize("foot", ["cone", "wedge", "roller"])
@pytest.mark.parametrize("size", [0.07, 0.085, 0.10])
@pytest.mark.parametrize("pitch_free", [True, False])
def test_biped_variants(foot, size, pitch_free):
    m = biped_model(foot=foot, foot_size=size, pitch_free=pitch_free, sand=True)
    _assert_common(m)
    _assert_sand_scene(m, 0.02)  # models.biped.RESOLUTION
    assert _custom(m)[0]["mjrft:bodies"].split() == ["left_foot", "right_foot"]
    assert _robot_mass(m) == pytest.approx(1.6, rel=0.02)
    assert m.nu == 8
    assert all(abs(m.actuator(a).forcerange[1] - 2.5) < 1e-9 for a in range(m.nu))
    root = [m.joint(j).name for j in range(m.njnt) if m.jnt_bodyid[j] == m.body("torso").id]
    assert root == (["rootx", "rootz", "rooty"] if pitch_free else ["rootx", "rootz"])
    lo, hi = _z_extent(m)
    assert hi - lo == pytest.approx(0.303 - 0.085 / 2 + size / 2, abs=1e-3)
    # planar: every hinge is about y, slides along x / z
    for j in range(m.njnt):
        if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE:
            np.testing.assert_allclose(m.jnt_axis[j], [0, 1, 0])
    _rollout(m)
    _rollout(biped_model(foot=foot, foot_size=size, pitch_free=pitch_free, sand=False))


def test_biped_height_and_foot_dims():
    for foot in ("cone", "wedge", "roller"):
        m = biped_model(foot=foot)
        lo, hi = _z_extent(m)
        assert hi - lo == pytest.approx(0.303, abs=1e-3)
    m = biped_model(foot="roller")
    assert 2 * m.geom("left_foot").size[0] == pytest.approx(0.085)
    # the cone: circular sole of 8.5 cm (area pi 4.25^2 cm^2), 7.5 cm tall, sole centre 4.25 cm below the ankle
    m = biped_model(foot="cone")
    mid = m.geom_dataid[m.geom("left_foot").id]
    v = m.mesh_vert[m.mesh_vertadr[mid]: m.mesh_vertadr[mid] + m.mesh_vertnum[mid]]
    f = m.mesh_face[m.mesh_faceadr[mid]: m.mesh_faceadr[mid] + m.mesh_facenum[mid]]
    gid = m.geom("left_foot").id
    rot = np.empty(9)
    mujoco.mju_quat2Mat(rot, m.geom_quat[gid])
    v = v @ rot.reshape(3, 3).T + m.geom_pos[gid]  # mesh frame (MuJoCo's principal axes) -> foot frame
    z = v[:, 2]
    assert z.min() == pytest.approx(-0.0425, abs=1e-7) and z.max() - z.min() == pytest.approx(0.075, abs=1e-7)
    tri = v[f]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    sole = np.abs(cross[:, 2]) > 0.999 * np.linalg.norm(cross, axis=1)  # faces facing straight down
    assert 0.5 * np.linalg.norm(cross[sole], axis=1).sum() == pytest.approx(np.pi * 0.0425**2, rel=1e-6)  # float32 mesh
    assert m.site_pos[m.site("left_sole").id][2] == pytest.approx(-0.0425)
    with pytest.raises(ValueError, match="ambiguous.*cone.*roller"):
        biped_xml(foot="round")
    with pytest.raises(ValueError, match="foot_width"):
        biped_xml(foot="cone", foot_width=0.1)
    m = biped_model(foot="wedge")
    aabb = m.geom_aabb[m.geom("left_foot").id, 3:] * 2  # mesh box in its principal frame; check the extents
    assert sorted(aabb) == pytest.approx(sorted([0.085, 0.085, 0.075]), abs=1e-6)
    with pytest.raises(ValueError, match="foot"):
        biped_xml(foot="square")
    with pytest.raises(ValueError, match="foot_size"):
        biped_xml(foot_size=-0.01)


def test_biped_servos_move_legs():
    m = biped_model(sand=False, pitch_free=False)
    d = mujoco.MjData(m)
    d.ctrl[m.actuator("left_ankle").id] = 0.3
    for _ in range(500):
        mujoco.mj_step(m, d)
    assert d.qpos[m.joint("left_ankle").qposadr[0]] == pytest.approx(0.3, abs=0.05)


# ----------------------------------------------------------------- humanoid


@pytest.mark.parametrize("cutout", [False, True])
@pytest.mark.parametrize("width", [0.152, 0.178, 0.304])
def test_humanoid_variants(cutout, width):
    m = humanoid_model(foot_width=width, foot_cutout=cutout, sand=True)
    _assert_common(m)
    _assert_sand_scene(m, 0.02)
    assert _custom(m)[0]["mjrft:bodies"].split() == ["left_foot", "right_foot"]
    assert _robot_mass(m) == pytest.approx(50.0, rel=0.02)
    lo, hi = _z_extent(m)
    assert hi - lo == pytest.approx(1.2, abs=0.01)
    foot = m.body("left_foot")
    area = sum(4 * m.geom_size[g, 0] * m.geom_size[g, 1] for g in range(foot.geomadr[0], foot.geomadr[0] + foot.geomnum[0]))
    full = 0.229 * width
    assert area == pytest.approx(full / 2 if cutout else full, rel=1e-4)
    assert foot.geomnum[0] == (4 if cutout else 1)
    _rollout(m)


def test_humanoid_dofs_and_rigid_standing():
    m = humanoid_model(sand=False)
    names = {m.joint(j).name for j in range(m.njnt)}
    for side in ("left", "right"):
        for j in ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll",
                  "shoulder_pitch", "elbow"):
            assert f"{side}_{j}" in names
    assert "waist_yaw" in names and m.nu >= 17
    assert m.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    d = _rollout(m)
    assert d.qpos[2] > 0.7  # stands on the rigid floor with zero control


# ----------------------------------------------------------------- with the granular terrain


@pytest.mark.parametrize("name", [n for n in MODEL_NAMES if not n.endswith("rigid")])
def test_sand_models_rest_on_granular_terrain(name):
    """The MJCF <custom> set-up is accepted by mjrft.GranularTerrain and the robot is held up by the grains."""
    mjrft = pytest.importorskip("mjrft")
    if not hasattr(mjrft, "GranularTerrain"):
        pytest.skip("mjrft.GranularTerrain not available")
    m = mujoco.MjModel.from_xml_path(model_path(name))
    d = mujoco.MjData(m)
    z0 = _z_extent(m)[0]
    terrain = mjrft.GranularTerrain(m)
    assert set(terrain.body_ids) == {m.body(b).id for b in _custom(m)[0]["mjrft:bodies"].split()}
    terrain.step(d, 500)
    assert np.all(np.isfinite(d.qpos))
    mujoco.mj_forward(m, d)
    # lowest point sank a little into the bed but is far above the bed bottom (-0.3 m)
    lo = _z_extent(m, d)[0]
    assert z0 >= 0.0 and -0.1 < lo < 0.0
