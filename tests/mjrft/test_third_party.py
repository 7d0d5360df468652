"""A third-party MuJoCo model on sand, unchanged: floor option, collision geoms only, automatic resolution,
mesh elements that merge small triangles, integrators."""

from __future__ import annotations

import math
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.floor import FLOOR_PAIR_MARGIN
from mjrft.selection import AUTO_ELEMENTS, AUTO_MIN_RESOLUTION, auto_resolution
from mjrft.settings import resolve_settings
from mjrft.errors import TerrainStabilityWarning
from mjrft.geometry import discretize_geom, estimate_elements, geom_elements, mesh_element_count, surface_area


def icosphere(level: int, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and outward counter-clockwise faces of a subdivided icosahedron (20 * 4**level triangles)."""
    t = (1 + math.sqrt(5)) / 2
    corners = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
               (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    verts = [np.array(v, dtype=float) for v in corners]
    verts = [v / np.linalg.norm(v) for v in verts]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
             (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
             (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        cache: dict = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                cache[key] = len(verts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return radius * np.array(verts), np.array(faces)


FOOT_AXES = np.array([0.05, 0.05, 0.02])  # a flat ellipsoidal foot (stands without tipping)
FOOT_V, FOOT_F = icosphere(5, 1.0)  # 20480 triangles, edges 0.6-2.1 mm: a detailed mesh foot
FOOT_V = FOOT_V * FOOT_AXES
SHELL_V, SHELL_F = icosphere(2, 0.09)  # the visual-only shell around the body
FLOOR_Z = 0.05
MASS = 1.5


def _fmt(a) -> str:
    return " ".join(f"{x:.9g}" for x in np.ravel(a))


def robot_xml(floor: str | None = None, integrator: str = "Euler", extra_world: str = "", custom: str = "",
              extra: str = "") -> str:
    """A free body with a box torso on a detailed mesh foot and a visual-only mesh shell, above a
    plane floor at FLOOR_Z (the way a third-party model comes: the robot rests on MuJoCo's floor)."""
    floor = floor if floor is not None else f'<geom name="floor" type="plane" size="2 2 0.1" pos="0 0 {FLOOR_Z}"/>'
    return f"""<mujoco model="third_party">
  <option timestep="0.001" integrator="{integrator}"/>
  <asset>
    <mesh name="foot" vertex="{_fmt(FOOT_V)}" face="{_fmt(FOOT_F)}"/>
    <mesh name="shell" vertex="{_fmt(SHELL_V)}" face="{_fmt(SHELL_F)}"/>
  </asset>
  {custom}
  <worldbody>
    {floor}
    {extra_world}
    <body name="robot" pos="0 0 {FLOOR_Z + 0.03}">
      <freejoint/>
      <geom name="torso" type="box" size="0.05 0.05 0.02" pos="0 0 0.04" mass="{MASS - 0.5}"/>
      <geom name="foot" type="mesh" mesh="foot" mass="0.5"/>
      <geom name="shell" type="mesh" mesh="shell" contype="0" conaffinity="0" group="2" mass="0"/>
    </body>
    {extra}
  </worldbody>
</mujoco>"""


def gid(m, name: str) -> int:
    return mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, name)


def settle(m, terrain, seconds: float = 1.5):
    d = mujoco.MjData(m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TerrainStabilityWarning)
        terrain.step(d, int(round(seconds / m.opt.timestep)))
    return d


def test_two_lines_put_a_third_party_model_on_sand():
    xml = robot_xml()
    m = mujoco.MjModel.from_xml_string(xml)
    terrain = mjrft.GranularTerrain(m, floor="auto")
    # the floor is the sand surface; its contacts are gone in the loaded model, not in the XML
    assert terrain.floor == gid(m, "floor") and terrain.surface == pytest.approx(FLOOR_Z, abs=1e-12)
    assert (m.geom_contype[terrain.floor], m.geom_conaffinity[terrain.floor]) == (0, 0)
    assert terrain.floor_contacts == (1, 1)
    fresh = mujoco.MjModel.from_xml_string(xml)
    assert (fresh.geom_contype[gid(fresh, "floor")], fresh.geom_conaffinity[gid(fresh, "floor")]) == (1, 1)
    # collision geoms only: the visual shell is not cut into elements
    assert sorted(terrain.geom_ids.tolist()) == sorted([gid(m, "torso"), gid(m, "foot")])
    # automatic resolution, bounded count: far fewer elements than the foot has triangles
    assert terrain.resolution_auto and terrain.resolution >= AUTO_MIN_RESOLUTION
    assert terrain.n_elements <= 1.1 * AUTO_ELEMENTS and terrain.n_elements < len(FOOT_F) / 4
    foot = terrain.elem_geom == gid(m, "foot")
    mesh = int(m.geom_dataid[gid(m, "foot")])  # (MuJoCo stores the vertices in float32)
    va, fa = m.mesh_vertadr[mesh], m.mesh_faceadr[mesh]
    exact = surface_area("mesh", None, m.mesh_vert[va:va + m.mesh_vertnum[mesh]],
                         m.mesh_face[fa:fa + m.mesh_facenum[mesh]])
    np.testing.assert_allclose(terrain.area[foot].sum(), exact, rtol=1e-12)
    # it rests on the sand, not on the rigid floor, carrying its weight
    d = settle(m, terrain)
    assert d.ncon == 0
    weight = MASS * 9.81
    assert abs(terrain.wrench[:, 2].sum() / weight - 1.0) < 0.02
    sink = FLOOR_Z - (d.geom_xpos[gid(m, "foot")][2] - FOOT_AXES[2])
    assert 0.0 < sink < 2 * FOOT_AXES[2]
    assert np.all(np.isfinite(d.qpos)) and np.abs(d.qvel).max() < 0.05


def test_the_same_model_on_the_rigid_floor_rests_on_contacts():
    """Control: without the terrain the body stands on MuJoCo's floor (so the test above is not vacuous)."""
    m = mujoco.MjModel.from_xml_string(robot_xml())
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, 1500)
    assert d.ncon > 0
    assert d.geom_xpos[gid(m, "foot")][2] - FOOT_AXES[2] == pytest.approx(FLOOR_Z, abs=2e-3)


@pytest.mark.parametrize("integrator", ["Euler", "implicit", "implicitfast"])
def test_resting_weight_balance_for_each_supported_integrator(integrator):
    m = mujoco.MjModel.from_xml_string(robot_xml(integrator=integrator))
    terrain = mjrft.GranularTerrain(m, floor="auto")
    settle(m, terrain, 1.0)
    assert abs(terrain.wrench[:, 2].sum() / (MASS * 9.81) - 1.0) < 0.02


def test_rk4_is_refused_with_the_reason():
    m = mujoco.MjModel.from_xml_string(robot_xml(integrator="RK4"))
    terrain = mjrft.GranularTerrain(m, floor="auto")  # compute() alone does not integrate: allowed
    d = mujoco.MjData(m)
    with pytest.raises(ValueError, match=r"does not support the RK4 integrator: MuJoCo's mj_step1/mj_step2 split .* "
                                         r"semi-implicit Euler.*IMPLICITFAST"):
        terrain.step(d)
    with pytest.raises(ValueError, match="RK4 .* four stages"):
        terrain.install()
    assert mujoco.get_mjcb_passive() is None and d.time == 0.0
    mujoco.mj_forward(m, d)
    terrain.compute(d)
    assert np.all(np.isfinite(terrain.wrench))


def test_floor_from_the_models_custom_section_and_auto_resolution_text():
    custom = ('<custom><text name="mjrft:floor" data="auto"/><text name="mjrft:resolution" data="auto"/>'
              '<text name="mjrft:medium" data="glass3_cp"/></custom>')
    m = mujoco.MjModel.from_xml_string(robot_xml(custom=custom))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # mjrft:floor is a known key
        terrain = mjrft.GranularTerrain(m)
    assert terrain.floor == gid(m, "floor") and terrain.medium.name == "glass3_cp" and terrain.resolution_auto
    assert resolve_settings(mujoco.MjModel.from_xml_string(robot_xml(custom=custom))).resolution == terrain.resolution
    both = custom.replace("</custom>", '<numeric name="mjrft:surface" data="0"/></custom>')
    with pytest.raises(ValueError, match="<custom> gives both mjrft:floor and mjrft:surface; keep one of them"):
        mjrft.GranularTerrain(mujoco.MjModel.from_xml_string(robot_xml(custom=both)))
    # an argument wins over the file: surface= given, the file's floor is not used (and keeps its contacts)
    m = mujoco.MjModel.from_xml_string(robot_xml(custom=both))
    assert mjrft.GranularTerrain(m, surface=0.02).floor is None and m.geom_contype[gid(m, "floor")] == 1


def test_named_box_floor_and_its_height():
    box = f'<geom name="ground" type="box" size="1 1 0.1" pos="0 0 {FLOOR_Z - 0.1}" euler="0 0 0.3"/>'
    m = mujoco.MjModel.from_xml_string(robot_xml(floor=box))
    terrain = mjrft.GranularTerrain(m, floor="ground")
    assert terrain.surface == pytest.approx(FLOOR_Z, abs=1e-12) and m.geom_contype[gid(m, "ground")] == 0
    # a box standing on its side: its top is the half size along its vertical axis
    side = f'<geom name="ground" type="box" size="0.1 1 1" pos="0 0 {FLOOR_Z - 0.1}" euler="0 90 0"/>'
    m = mujoco.MjModel.from_xml_string(robot_xml(floor=side))
    assert mjrft.GranularTerrain(m, floor="auto").surface == pytest.approx(FLOOR_Z, abs=1e-9)


def test_auto_floor_takes_the_highest_top_under_the_robot():
    # a step beside the robot and a platform above the floor away from it are not the floor
    extra = ('<geom name="step" type="box" size="0.2 0.2 0.1" pos="1 0 0.1"/>'
             '<geom name="wall" type="plane" size="1 1 0.1" pos="-1 0 0" zaxis="1 0 0"/>'
             '<geom name="decal" type="plane" size="1 1 0.1" pos="0 0 -0.2" contype="0" conaffinity="0"/>')
    m = mujoco.MjModel.from_xml_string(robot_xml(extra_world=extra))
    terrain = mjrft.GranularTerrain(m, floor="auto")
    assert terrain.floor == gid(m, "floor")
    assert m.geom_contype[gid(m, "step")] == 1  # only the floor loses its contacts


def test_auto_floor_errors_list_the_candidates():
    twin = f'<geom name="floor2" type="plane" size="2 2 0.1" pos="1 0 {FLOOR_Z}"/>'
    m = mujoco.MjModel.from_xml_string(robot_xml(extra_world=twin))
    with pytest.raises(ValueError, match=r"floor='auto' is ambiguous: 2 geoms have the highest top 0.05 m .*"
                                         r"'floor', 'floor2'.*name the floor"):
        mjrft.GranularTerrain(m, floor="auto")
    assert m.geom_contype[gid(m, "floor")] == 1  # a failed constructor leaves the model as it was
    # the other plane at the same height stays a rigid floor the robot stands on: named in a warning
    with pytest.warns(mjrft.SandContactWarning, match=r"geom 'floor' \(plane, top 0.05 m\) is a collision floor "
                                                      r"under the robot at or above the sand surface"):
        assert mjrft.GranularTerrain(m, floor="floor2").floor == gid(m, "floor2")
    none = '<geom name="wall" type="plane" size="1 1 0.1" pos="-1 0 0" zaxis="1 0 0"/>'
    m = mujoco.MjModel.from_xml_string(robot_xml(floor=none))
    with pytest.raises(ValueError, match=r"found no collision plane, box or hfield .* 'wall' \(plane, tilted"):
        mjrft.GranularTerrain(m, floor="auto")
    with pytest.raises(ValueError, match=r"floor geom 'wall' cannot be the sand surface: it is tilted"):
        mjrft.GranularTerrain(m, floor="wall")
    with pytest.raises(ValueError, match=r"floor geom 'torso' cannot be the sand surface: it is a box"
                                         r"|floor geom 'torso' cannot be the sand surface: it is on a moving body"):
        mjrft.GranularTerrain(m, floor="torso")
    with pytest.raises(mjrft.errors.UnknownNameError, match=r"unknown floor geom 'flor'; valid choices: auto, wall"):
        mjrft.GranularTerrain(m, floor="flor")
    for bad in (0.05, True, ["floor"]):
        with pytest.raises(ValueError, match=r"floor must be None, 'auto' or a geom name/id, got"):
            mjrft.GranularTerrain(m, floor=bad)
    m = mujoco.MjModel.from_xml_string(robot_xml())
    with pytest.raises(ValueError, match="floor='auto' and surface=0.0 both give the sand surface"):
        mjrft.GranularTerrain(m, floor="auto", surface=0.0)


def test_hfield_floor_becomes_the_height_field_surface():
    asset = ('<asset><hfield name="hf" nrow="3" ncol="3" size="1 1 0.1 0.05" '
             'elevation="0 0 0  0 0.5 0  0 0 0"/></asset>')
    m = mujoco.MjModel.from_xml_string(robot_xml(floor=f'<geom name="terrain" type="hfield" hfield="hf" '
                                                       f'pos="0 0 {FLOOR_Z}"/>', custom=asset))
    terrain = mjrft.GranularTerrain(m, floor="auto")
    assert terrain.floor == gid(m, "terrain") == terrain.surface_hfield
    assert terrain.surface_height(0.0, 0.0) == pytest.approx(FLOOR_Z + 0.1)  # MuJoCo scales the samples to [0, 1]
    assert terrain.surface_height(0.5, 0.5) == pytest.approx(FLOOR_Z + 0.025)
    assert terrain.surface_height(1.0, 1.0) == pytest.approx(FLOOR_Z)
    assert m.geom_contype[terrain.floor] == 0


def test_an_explicit_contact_pair_with_the_floor_is_taken_out_of_reach():
    extra = '<body name="ball" pos="0.5 0 0.2"><freejoint/><geom name="ball" type="sphere" size="0.02"/></body>'
    pair = '<contact><pair geom1="ball" geom2="floor"/></contact>'
    m = mujoco.MjModel.from_xml_string(robot_xml(extra=extra, custom=pair))
    terrain = mjrft.GranularTerrain(m, floor="auto", bodies=["robot"])
    assert m.pair_margin[0] == FLOOR_PAIR_MARGIN
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d, 400)  # the ball (not a granular body) falls through the removed floor
    assert d.ncon == 0 and d.xpos[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "ball")][2] < 0.0
    assert terrain.floor == gid(m, "floor")


def test_visual_only_geoms_are_selected_only_when_named_or_when_a_body_has_nothing_else():
    m = mujoco.MjModel.from_xml_string(robot_xml())
    torso, foot, shell = gid(m, "torso"), gid(m, "foot"), gid(m, "shell")
    assert mjrft.GranularTerrain(m, bodies=["robot"]).geom_ids.tolist() == [torso, foot]
    named = mjrft.GranularTerrain(m, geoms=["foot", "shell"])
    assert named.geom_ids.tolist() == [foot, shell]
    # a body whose geoms are all visual-only (a kinematic rig) keeps them
    rig = ('<body name="rig" pos="1 1 0.3"><geom name="paddle" type="box" size=".02 .02 .002" contype="0" '
           'conaffinity="0"/></body>')
    m = mujoco.MjModel.from_xml_string(robot_xml(extra=rig))
    assert mjrft.GranularTerrain(m, bodies=["rig"]).geom_ids.tolist() == [gid(m, "paddle")]
    assert gid(m, "paddle") not in mjrft.GranularTerrain(m).geom_ids  # the default takes collision geoms only


def test_auto_resolution_bounds_the_count_and_keeps_small_robots_at_the_finest_size():
    m = mujoco.MjModel.from_xml_string(robot_xml())
    ids = [gid(m, "torso"), gid(m, "foot")]
    assert auto_resolution(m, ids) == AUTO_MIN_RESOLUTION  # small robot: 5 mm, under the target count
    assert estimate_elements(m, ids, AUTO_MIN_RESOLUTION) <= AUTO_ELEMENTS
    big = ('<body name="big" pos="0 0 2"><freejoint/><geom name="hull" type="box" size="0.6 0.4 0.2"/>'
           '<geom name="leg" type="capsule" fromto="0 0 0 0 0 -0.8" size="0.08"/></body>')
    m = mujoco.MjModel.from_xml_string(robot_xml(extra=big))
    terrain = mjrft.GranularTerrain(m, bodies=["big"])
    area = surface_area("box", (0.6, 0.4, 0.2)) + surface_area("capsule", (0.08, 0.4))
    assert terrain.resolution == pytest.approx(math.sqrt(area / AUTO_ELEMENTS), rel=0.1)
    assert 0.5 * AUTO_ELEMENTS < terrain.n_elements <= 1.1 * AUTO_ELEMENTS
    with pytest.raises(ValueError, match=r"resolution must be a length in m or 'auto', got 'fine'"):
        mjrft.GranularTerrain(m, resolution="fine")


# ---------------------------------------------------------------------------------------------- mesh merging
@pytest.mark.parametrize("res", [0.003, 0.006, 0.012, 0.03, 0.1])
def test_mesh_merging_keeps_area_centroid_and_bounded_projection(res):
    el = geom_elements("mesh", None, res, FOOT_V, FOOT_F)
    assert len(el) == mesh_element_count(FOOT_V, FOOT_F, res)
    v0, v1, v2 = (FOOT_V[FOOT_F[:, i]] for i in range(3))
    cross = np.cross(v1 - v0, v2 - v0)
    tri_area = 0.5 * np.linalg.norm(cross, axis=1)
    np.testing.assert_allclose(el.area.sum(), tri_area.sum(), rtol=1e-12)
    # sums of area x (anything linear in position) are exact: the area-weighted centroid
    np.testing.assert_allclose((el.area[:, None] * el.pos).sum(0), (tri_area[:, None] * (v0 + v1 + v2) / 3).sum(0),
                               atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(el.normal, axis=1), 1.0)
    # the elements are about the resolution: the count follows area / res^2 (x 1-3: cells cut the surface)
    area = tri_area.sum()
    if res == 0.003:  # most triangles' longest edge is above res / 2: one element each, as without merging
        assert 0.9 * len(FOOT_F) < len(el) < len(FOOT_F)
    else:
        assert len(el) < len(FOOT_F) / 4
    if res in (0.006, 0.012):
        assert area / res**2 < len(el) < 3.5 * area / res**2
    # summed area vectors (the projected area a pressure acts on): each element's total area along its
    # mean normal overstates |sum of its triangles' area vectors| by at most 1 - cos(spread); measured here
    lower = el.normal[:, 2] < 0
    exact = -np.pi * FOOT_AXES[0] * FOOT_AXES[1]
    assert abs((el.area[lower] * el.normal[lower, 2]).sum() / exact - 1.0) < 0.02


def test_mesh_triangles_larger_than_half_the_resolution_are_split_as_before():
    v = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.05, 0], [0.002, 0.002, 0.0], [0.003, 0.002, 0.0]], dtype=float)
    f = np.array([[0, 1, 2]])
    for res in (0.01, 0.2, 0.3):  # the triangle's longest edge 0.112 m is more than res / 2
        el = geom_elements("mesh", None, res, v, f)
        k = math.ceil(math.hypot(0.1, 0.05) / res)
        assert len(el) == k * k
    # a small triangle next to a big one: the big one is split as before, the small one is its own cluster
    el = geom_elements("mesh", None, 0.01, v, np.array([[0, 1, 2], [0, 3, 4]]))
    k = math.ceil(math.hypot(0.1, 0.05) / 0.01)
    assert len(el) == k * k + 1
    np.testing.assert_allclose(el.pos[-1], v[[0, 3, 4]].mean(axis=0))


def test_bundled_and_many_triangle_meshes_estimate_exactly():
    m = mujoco.MjModel.from_xml_string(robot_xml())
    for res in (0.002, 0.005, 0.02):
        assert estimate_elements(m, [gid(m, "foot")], res) == len(discretize_geom(m, gid(m, "foot"), res))


# ---------------------------------------------------------------------------------------------- bundled scenes
@pytest.mark.parametrize("name", ["hexapod", "hexapod_small", "hexapod_shoal", "biped", "biped_wedge", "humanoid",
                                  "humanoid_cutout", "plate_rig", "leg_rig"])
def test_bundled_scenes_keep_every_geom_of_their_granular_bodies(name):
    """The collision-geoms-only rule changes no bundled scene: each selects every supported geom of the bodies its
    <custom> (or, for the kinematic rigs whose geoms collide with nothing, mjrft.tools.rigs) names."""
    from mjrft.selection import _SUPPORTED_GEOMS
    from mjrft.settings import custom_entries
    from mjrft.models import model_path

    m = mujoco.MjModel.from_xml_path(model_path(name))
    bodies = custom_entries(m).get("bodies", "plate" if name == "plate_rig" else "leg").split()
    ids = {mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, b) for b in bodies}
    every = [g for g in range(m.ngeom) if m.geom_bodyid[g] in ids and m.geom_type[g] in _SUPPORTED_GEOMS]
    terrain = mjrft.GranularTerrain(m, bodies=bodies, resolution=0.01)
    assert terrain.geom_ids.tolist() == every and len(every) > 0
