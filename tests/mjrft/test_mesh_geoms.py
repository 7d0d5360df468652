"""Mesh collision geoms in the sand: a box given as a triangle mesh (MuJoCo's compiled mesh, re-centred by the
compiler) feels the force of the box primitive of the same size, also when its faces are cut into the long thin
slivers of a CAD export; flipped normals or doubled areas are rejected by the same comparison."""

from __future__ import annotations

import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft.errors import TerrainStabilityWarning, ValidityRangeWarning
from mjrft.geometry import discretize_geom

HALF = np.array([0.04, 0.03, 0.02])  # the box's half-sizes (m)
RES = 0.01


def box_mesh(strips: int = 1, flip: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """A closed box of half-sizes HALF centred at the origin, outward counter-clockwise faces; each face is
    cut into ``strips`` strips (two triangles each) along its first axis: thin slivers for many strips."""
    verts, faces = [], []
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for sign in (1.0, -1.0):
            base = len(verts)
            for i in range(strips + 1):
                for j in range(2):
                    p = np.zeros(3)
                    p[axis] = sign * HALF[axis]
                    p[u] = -HALF[u] + 2 * HALF[u] * i / strips
                    p[v] = -HALF[v] + 2 * HALF[v] * j
                    verts.append(p)
            for i in range(strips):
                a, b, c, d = base + 2 * i, base + 2 * i + 2, base + 2 * i + 3, base + 2 * i + 1
                tri = [(a, b, c), (a, c, d)] if sign > 0 else [(a, c, b), (a, d, c)]
                faces += [t[::-1] if flip else t for t in tri]
    return np.array(verts), np.array(faces)


def scene(strips: int = 1, flip: bool = False) -> mujoco.MjModel:
    v, f = box_mesh(strips, flip)
    fmt = lambda a: " ".join(f"{x:.12g}" for x in np.ravel(a))  # noqa: E731
    return mujoco.MjModel.from_xml_string(f"""<mujoco>
  <option timestep="0.001"/>
  <asset><mesh name="boxmesh" vertex="{fmt(v)}" face="{fmt(f)}"/></asset>
  <worldbody>
    <geom name="floor" type="plane" size="2 2 0.1"/>
    <body name="prim" pos="-0.3 0 0.1"><freejoint/><geom name="prim" type="box" size="{fmt(HALF)}"/></body>
    <body name="mesh" pos="0.3 0 0.1"><freejoint/><geom name="mesh" type="mesh" mesh="boxmesh"/></body>
  </worldbody>
</mujoco>""")


def push(m: mujoco.MjModel, top_depth: float, steps: int = 20, scale_mesh_area: float = 1.0,
         flip_mesh_normals: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Both boxes at the same depth (their top ``top_depth`` below the surface; negative: sticking out), tilted
    the same way, moving down and sideways at the same velocity: the granular wrench on each after ``steps``
    evaluations (the elements' memory built up the same way)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityRangeWarning)
        warnings.simplefilter("ignore", TerrainStabilityWarning)  # nothing is stepped: only the force is compared
        terrain = mjrft.GranularTerrain(m, "poppy_cp", "rft", bodies=["prim", "mesh"], floor="floor", resolution=RES)
        mesh = terrain.elem_body == m.body("mesh").id
        terrain.area[mesh] *= scale_mesh_area
        if flip_mesh_normals:
            terrain.terrain_model.elements.lnrm[mesh] *= -1.0
        d = mujoco.MjData(m)
        quat = np.array([np.cos(0.15), np.sin(0.15) * 0.6, np.sin(0.15) * 0.8, 0.0])
        for name, x in (("prim", -0.3), ("mesh", 0.3)):
            j = m.body(name).jntadr[0]
            qa, va = m.jnt_qposadr[j], m.jnt_dofadr[j]
            d.qpos[qa:qa + 3] = [x, 0.0, -top_depth - HALF[2]]
            d.qpos[qa + 3:qa + 7] = quat
            d.qvel[va:va + 3] = [0.05, 0.02, -0.08]
        mujoco.mj_forward(m, d)
        for _ in range(steps):
            terrain.compute(d)
    return terrain.wrench[m.body("prim").id].copy(), terrain.wrench[m.body("mesh").id].copy()


def close(a: np.ndarray, b: np.ndarray) -> float:
    """Largest force difference over the primitive's force magnitude."""
    return float(np.abs(a[:3] - b[:3]).max() / np.linalg.norm(a[:3]))


def test_mesh_box_elements_are_the_box_surface():
    m = scene()
    el = discretize_geom(m, m.geom("mesh").id, RES)
    prim = discretize_geom(m, m.geom("prim").id, RES)
    assert el.total_area == pytest.approx(prim.total_area, rel=1e-6)  # the mesh is stored in float32
    # outward: every element's normal points away from the body's centre, whatever MuJoCo did to the frame
    centre = m.body_ipos[m.body("mesh").id]
    assert np.all(np.einsum("ij,ij->i", el.pos - centre, el.normal) > 0)


@pytest.mark.parametrize("strips", [1, 40], ids=["two-triangle faces", "sliver faces"])
def test_mesh_box_feels_the_force_of_the_box_primitive(strips):
    m = scene(strips)
    if strips > 1:  # 40 strips of 2 mm x 6 cm per face: slivers, merged into elements of about RES
        n_mesh = len(discretize_geom(m, m.geom("mesh").id, RES))
        n_prim = len(discretize_geom(m, m.geom("prim").id, RES))
        assert n_mesh < 2 * n_prim  # measured 208 against 208 (24,800 pieces unmerged)
    prim, mesh = push(m, top_depth=0.03)  # fully under the surface: depth-linear loads are exact sums
    assert np.linalg.norm(prim[:3]) > 50.0  # a real load (measured 141 N)
    assert close(prim, mesh) < 1e-5  # measured 5e-8 with either triangulation (float32 vertices)
    prim, mesh = push(m, top_depth=-0.02)  # half out: the surface cuts through elements
    assert close(prim, mesh) < 0.01  # measured 6e-4 (two-triangle faces), 1.6e-4 (slivers) of 37 N


def test_flipped_normals_and_doubled_areas_are_rejected():
    prim, mesh = push(scene(), top_depth=0.03, flip_mesh_normals=True)
    assert close(prim, mesh) > 0.3  # measured 0.51
    prim, mesh = push(scene(), top_depth=0.03, scale_mesh_area=2.0)
    assert abs(close(prim, mesh) - 1.0) < 0.05  # twice the force (measured 0.994 more)


def test_sliver_merging_leaves_well_shaped_triangles_alone():
    """A triangle whose height is above 5 % of its longest edge is split into k^2 pieces as before."""
    m = scene(strips=4)  # strips of 2 cm x 6 cm: not slivers
    el = discretize_geom(m, m.geom("mesh").id, RES)
    v, f = box_mesh(4)
    e = np.linalg.norm(np.stack([v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 1]], v[f[:, 0]] - v[f[:, 2]]]), axis=2)
    k = np.ceil(e.max(axis=0) / RES - 1e-9)
    assert len(el) == int((k**2).sum())


def test_an_inside_out_mesh_is_refused_with_the_reason():
    """MuJoCo compiles a closed mesh whose faces wind clockwise (it takes the volume's magnitude), but its normals
    point inward: the terrain refuses it, naming the geom, instead of pushing it the wrong way."""
    m = scene(flip=True)
    assert m.body_mass[m.body("mesh").id] == pytest.approx(m.body_mass[m.body("prim").id], rel=1e-6)
    with pytest.raises(ValueError, match=r"mesh geom \d+ 'mesh' \(mesh 'boxmesh'\) is inside out.*reverse the order"):
        mjrft.GranularTerrain(m, "poppy_cp", "rft", bodies=["prim", "mesh"], floor="floor", resolution=RES)
    # an open mesh (the box without its top face) has no inside and is not checked
    v, f = box_mesh()
    top = np.all(v[f][:, :, 2] > HALF[2] - 1e-9, axis=1)
    fmt = lambda a: " ".join(f"{x:.12g}" for x in np.ravel(a))  # noqa: E731
    m = mujoco.MjModel.from_xml_string(f"""<mujoco><asset><mesh name="cup" vertex="{fmt(v)}" face="{fmt(f[~top][:, ::-1])}"/>
  </asset><worldbody><geom name="floor" type="plane" size="1 1 .1"/>
  <body name="cup" pos="0 0 .1"><freejoint/><geom type="mesh" mesh="cup" mass="0.1"/></body></worldbody></mujoco>""")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert mjrft.GranularTerrain(m, "poppy_cp", bodies=["cup"], floor="floor", resolution=RES).n_elements > 0


def test_auto_resolution_takes_the_meshes_floor_of_elements_as_its_budget_and_says_so():
    """A mesh keeps one element per direction bin of its faces' normals however large the element size (this box
    mesh: 12). With a budget below that floor, resolution='auto' coarsens only until it reaches the floor, and warns,
    instead of enlarging the size sixteen-fold far past the robot (the check fails for a loop that coarsens towards
    the budget: from 12 elements at a budget of 3 it doubles the size each time, to kilometres). Control: a budget
    the mesh can meet gives no warning and at most 10 % more elements."""
    from mjrft.selection import auto_resolution

    m = scene()
    mesh = [m.geom("mesh").id]
    with pytest.warns(UserWarning, match=r"cannot keep these geoms to about 3 elements: at any element size they "
                                         r"give at least 12 .* which gives 1[23]\."):
        res = auto_resolution(m, mesh, target=3)
    assert res < 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = auto_resolution(m, mesh, target=40)
    assert len(discretize_geom(m, mesh[0], res)) <= 44
