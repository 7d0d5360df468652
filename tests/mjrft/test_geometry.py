"""Tests of mjrft.geometry: surface elements of MuJoCo geoms."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mjrft.geometry import (GEOM_TYPES, Elements, discretize_geom, element_count, exposed, exposed_elements,
                            geom_elements, inside_geom, surface_area)

RES = 0.005  # default resolution (m)

# Unit cube [0, 1]^3, faces counter-clockwise seen from outside.
CUBE_V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
CUBE_F = np.array([
    [0, 1, 3], [0, 3, 2],  # x = 0
    [4, 6, 7], [4, 7, 5],  # x = 1
    [0, 4, 5], [0, 5, 1],  # y = 0
    [2, 3, 7], [2, 7, 6],  # y = 1
    [0, 2, 6], [0, 6, 4],  # z = 0
    [1, 5, 7], [1, 7, 3],  # z = 1
])
TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def _mesh_kwargs(vertices, faces, scale=1.0):
    return {"mesh_vertices": scale * vertices, "mesh_faces": faces}


# (type, size, mesh kwargs, volume, implicit surface residual f(p) -> 0 on the surface)
def _box_res(h):
    return lambda p: np.max(np.abs(p) / h, axis=1) - 1.0


def _sphere_res(r):
    return lambda p: np.linalg.norm(p, axis=1) / r - 1.0


def _cyl_res(r, h):
    def f(p):
        rho, z = np.linalg.norm(p[:, :2], axis=1), np.abs(p[:, 2])
        return np.maximum(rho / r, z / h) - 1.0
    return f


def _capsule_res(r, h):
    def f(p):
        seg = np.stack([np.zeros(len(p)), np.zeros(len(p)), np.clip(p[:, 2], -h, h)], axis=1)
        return np.linalg.norm(p - seg, axis=1) / r - 1.0
    return f


def _ellipsoid_res(abc):
    return lambda p: np.sum((p / abc) ** 2, axis=1) - 1.0


def _cube_res(side):
    c = 0.5 * side
    return lambda p: np.max(np.abs(p - c), axis=1) / c - 1.0


SHAPES = {
    "box": ("box", (0.05, 0.1, 0.02), {}, 8 * 0.05 * 0.1 * 0.02, _box_res(np.array([0.05, 0.1, 0.02]))),
    "sphere": ("sphere", (0.1,), {}, 4 / 3 * math.pi * 0.1**3, _sphere_res(0.1)),
    "cylinder": ("cylinder", (0.05, 0.1), {}, math.pi * 0.05**2 * 0.2, _cyl_res(0.05, 0.1)),
    "capsule": ("capsule", (0.03, 0.1), {}, math.pi * 0.03**2 * 0.2 + 4 / 3 * math.pi * 0.03**3,
                _capsule_res(0.03, 0.1)),
    "ellipsoid": ("ellipsoid", (0.1, 0.05, 0.03), {}, 4 / 3 * math.pi * 0.1 * 0.05 * 0.03,
                  _ellipsoid_res(np.array([0.1, 0.05, 0.03]))),
    "mesh": ("mesh", None, _mesh_kwargs(CUBE_V, CUBE_F, 0.08), 0.08**3, _cube_res(0.08)),
}
CENTRES = {k: np.zeros(3) for k in SHAPES}
CENTRES["mesh"] = np.full(3, 0.04)


def _check_closed_surface(el: Elements, area, volume, residual, centre, *, area_tol=1e-9, vol_tol=1e-9):
    assert isinstance(el, Elements)
    assert el.pos.shape == (len(el), 3) and el.normal.shape == (len(el), 3) and el.area.shape == (len(el),)
    assert el.pos.dtype == el.normal.dtype == el.area.dtype == np.float64
    assert np.all(np.isfinite(el.pos)) and np.all(np.isfinite(el.normal)) and np.all(np.isfinite(el.area))
    assert np.all(el.area >= 0)
    np.testing.assert_allclose(el.area.sum(), area, rtol=area_tol)
    np.testing.assert_allclose(np.linalg.norm(el.normal, axis=1), 1.0, atol=1e-12)
    scale = max(np.max(np.abs(el.pos - centre)), 1e-300)
    np.testing.assert_allclose(residual(el.pos), 0.0, atol=1e-9)
    # outward: for these convex shapes, the normal points away from the centre
    assert np.all(np.einsum("ij,ij->i", el.normal, el.pos - centre) > 0)
    # stepping along the normal leaves the body, stepping against it enters
    eps = 1e-4 * scale
    assert np.all(residual(el.pos + eps * el.normal) > 0)
    assert np.all(residual(el.pos - eps * el.normal) < 0)
    # divergence theorem: closed surface integral of n is 0; of (x . n) / 3 is the volume
    np.testing.assert_allclose(el.normal.T @ el.area, 0.0, atol=1e-9 * area)
    vol = np.einsum("ij,ij,i->", el.pos - centre, el.normal, el.area) / 3.0
    np.testing.assert_allclose(vol, volume, rtol=vol_tol)


def test_public_names():
    assert GEOM_TYPES == ("box", "capsule", "cylinder", "sphere", "ellipsoid", "mesh")
    assert set(SHAPES) == set(GEOM_TYPES)


@pytest.mark.parametrize("name", list(SHAPES))
@pytest.mark.parametrize("resolution", [RES, 0.002, 0.03, 1.0])
def test_closed_surfaces(name, resolution):
    gtype, size, kw, volume, residual = SHAPES[name]
    el = geom_elements(gtype, size, resolution, **kw)
    area = surface_area(gtype, size, **kw)
    exact = name != "ellipsoid"
    _check_closed_surface(el, area, volume, residual, CENTRES[name],
                          area_tol=1e-9 if exact else 1e-3, vol_tol=1e-9 if name in ("box", "cylinder",
                          "sphere", "capsule", "mesh") else 0.03)


@pytest.mark.parametrize("name", list(SHAPES))
def test_count_grows_as_resolution_shrinks(name):
    gtype, size, kw, *_ = SHAPES[name]
    counts = [len(geom_elements(gtype, size, r, **kw)) for r in (1.0, 0.03, 0.01, 0.005)]
    assert counts == sorted(counts) and counts[-1] > counts[1] > counts[0]


@pytest.mark.parametrize("name", list(SHAPES))
def test_element_count_is_the_discretisers_count(name):
    """element_count counts the cells without building them: the count auto_resolution coarsens by."""
    gtype, size, kw, *_ = SHAPES[name]
    rng = np.random.default_rng(7)
    for r in (1.0, 0.03, 0.0125, 0.01, 0.005, 0.002, *rng.uniform(0.002, 0.05, 20)):
        assert element_count(gtype, size, r, **kw) == len(geom_elements(gtype, size, r, **kw)), r
    if name != "mesh":  # a wrong shape's count is told apart (control)
        other = "sphere" if name != "sphere" else "box"
        assert element_count(SHAPES[other][0], SHAPES[other][1], 0.005) != len(geom_elements(gtype, size, 0.005, **kw))


def test_coarse_resolution_still_covers_every_face():
    assert len(geom_elements("box", (0.01, 0.01, 0.01), 10.0)) == 6
    sph = geom_elements("sphere", (0.01,), 10.0)
    assert len(sph) == 2 * 2 * 4  # 2 hemispheres x 2 bands x 4 sectors
    assert len(geom_elements("mesh", None, 10.0, TET_V, TET_F)) == 4
    assert len(geom_elements("cylinder", (0.01, 0.01), 10.0)) == 4 + 4 + 4


def test_box_element_size_respects_resolution():
    el = geom_elements("box", (0.05, 0.1, 0.02), 0.01)
    # faces 0.1 x 0.2 -> 10 x 20 cells, 0.2 x 0.04 -> 20 x 4, 0.04 x 0.1 -> 4 x 10
    assert len(el) == 2 * (10 * 20 + 20 * 4 + 4 * 10)
    np.testing.assert_allclose(el.area, 1e-4)


def test_sphere_zones_are_exact():
    r = 0.1
    el = geom_elements("sphere", (r,), 0.01)
    up = el.normal[:, 2] > 0
    # exact projected area of each hemisphere: sum of n_z * area = pi r^2
    np.testing.assert_allclose((el.normal[up, 2] * el.area[up]).sum(), math.pi * r * r, rtol=1e-12)
    # bands roughly square: elements near the equator have edge ~ resolution
    eq = np.abs(el.normal[:, 2]) < 0.05
    assert np.all(np.sqrt(el.area[eq]) < 0.0105) and np.all(np.sqrt(el.area[eq]) > 0.005)


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(["box", "sphere", "cylinder", "capsule", "ellipsoid"]),
       size=st.tuples(*[st.floats(0.002, 0.2)] * 3),
       resolution=st.floats(0.004, 0.5))
def test_random_sizes(name, size, resolution):
    if name == "box":
        h = np.array(size)
        args = (size, 8 * np.prod(h), _box_res(h))
    elif name == "sphere":
        args = (size[:1], 4 / 3 * math.pi * size[0] ** 3, _sphere_res(size[0]))
    elif name == "cylinder":
        r, h = size[:2]
        args = (size[:2], 2 * math.pi * r * r * h, _cyl_res(r, h))
    elif name == "capsule":
        r, h = size[:2]
        args = (size[:2], 2 * math.pi * r * r * h + 4 / 3 * math.pi * r**3, _capsule_res(r, h))
    else:
        abc = np.array(size)
        args = (size, 4 / 3 * math.pi * np.prod(abc), _ellipsoid_res(abc))
    sz, volume, residual = args
    el = geom_elements(name, sz, resolution)
    area = surface_area(name, sz)
    ell = name == "ellipsoid"
    # a coarse or very eccentric ellipsoid is only crudely faceted: check its volume tightly only when fine
    fine = ell and resolution <= 0.1 * max(size) and max(size) <= 10 * min(size)
    _check_closed_surface(el, area, volume, residual, np.zeros(3),
                          area_tol=1e-2 if ell else 1e-9, vol_tol=(0.01 if fine else 0.5) if ell else 1e-9)


@settings(max_examples=30, deadline=None)
@given(abc=st.tuples(*[st.floats(1e-4, 1.0)] * 3), resolution=st.floats(0.02, 5.0))
def test_ellipsoid_area_any_aspect_ratio(abc, resolution):
    el = geom_elements("ellipsoid", abc, resolution)
    assert np.all(np.isfinite(el.normal))
    np.testing.assert_allclose(el.area.sum(), surface_area("ellipsoid", abc), rtol=1e-2)


def test_ellipsoid_surface_area_closed_forms():
    np.testing.assert_allclose(surface_area("ellipsoid", (0.3, 0.3, 0.3)), 4 * math.pi * 0.09, rtol=1e-12)
    a, c = 2.0, 1.0  # oblate spheroid
    e = math.sqrt(1 - c * c / (a * a))
    oblate = 2 * math.pi * a * a * (1 + (1 - e * e) / e * math.atanh(e))
    np.testing.assert_allclose(surface_area("ellipsoid", (a, a, c)), oblate, rtol=1e-10)
    a, c = 1.0, 3.0  # prolate spheroid
    e = math.sqrt(1 - a * a / (c * c))
    prolate = 2 * math.pi * a * a * (1 + c / (a * e) * math.asin(e))
    np.testing.assert_allclose(surface_area("ellipsoid", (a, a, c)), prolate, rtol=1e-10)
    np.testing.assert_allclose(surface_area("ellipsoid", (1.0, 2.0, 0.0)), 2 * math.pi * 2.0, rtol=1e-12)  # disk
    # triaxial against brute-force midpoint quadrature of |r_theta x r_phi|
    a, b, c = 3.0, 2.0, 0.5
    n = 800
    th = (np.arange(n) + 0.5) * math.pi / n
    ph = (np.arange(2 * n) + 0.5) * math.pi / n
    s, co = np.sin(th)[:, None], np.cos(th)[:, None]
    jac = s * np.sqrt((b * c * s * np.cos(ph)) ** 2 + (a * c * s * np.sin(ph)) ** 2 + (a * b * co) ** 2)
    np.testing.assert_allclose(surface_area("ellipsoid", (a, b, c)), jac.sum() * (math.pi / n) ** 2, rtol=1e-5)


def test_other_surface_areas():
    assert surface_area("box", (1, 2, 3)) == pytest.approx(8 * (2 + 6 + 3))
    assert surface_area("sphere", (2,)) == pytest.approx(16 * math.pi)
    assert surface_area("cylinder", (1, 2)) == pytest.approx(8 * math.pi + 2 * math.pi)
    assert surface_area("capsule", (1, 2)) == pytest.approx(8 * math.pi + 4 * math.pi)
    assert surface_area("mesh", None, CUBE_V, CUBE_F) == pytest.approx(6.0)
    assert surface_area("mesh", None, TET_V, TET_F) == pytest.approx(1.5 + math.sqrt(3) / 2)
    # MuJoCo size arrays always have 3 entries: extras are ignored
    assert surface_area(mujoco.mjtGeom.mjGEOM_SPHERE, np.array([2.0, 0.0, 0.0])) == pytest.approx(16 * math.pi)


def test_mesh_subdivision():
    v = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.05, 0]], dtype=float)
    f = np.array([[0, 1, 2]])
    el = geom_elements("mesh", None, 0.01, v, f)
    k = math.ceil(math.hypot(0.1, 0.05) / 0.01)
    assert len(el) == k * k
    np.testing.assert_allclose(el.area, 0.5 * 0.1 * 0.05 / k**2)
    np.testing.assert_allclose(el.normal, np.tile([0, 0, 1.0], (k * k, 1)))
    np.testing.assert_allclose(el.pos.mean(axis=0), v.mean(axis=0), atol=1e-15)  # congruent pieces
    x, y = el.pos[:, 0], el.pos[:, 1]
    assert np.all(el.pos[:, 2] == 0) and np.all(x > 0) and np.all(y > 0) and np.all(x / 0.1 + y / 0.05 < 1)
    # reversed winding flips the normal
    flipped = geom_elements("mesh", None, 0.01, v, f[:, ::-1])
    np.testing.assert_allclose(flipped.normal, -el.normal)


def test_mesh_degenerate_triangle():
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], dtype=float)
    el = geom_elements("mesh", None, 0.1, v, np.array([[0, 1, 2], [0, 0, 0], [0, 1, 3]]))
    assert np.all(np.isfinite(el.pos)) and np.all(np.isfinite(el.normal))
    np.testing.assert_allclose(np.linalg.norm(el.normal, axis=1), 1.0)
    np.testing.assert_allclose(el.area.sum(), 0.5)
    empty = geom_elements("mesh", None, 0.1, v, np.zeros((0, 3), dtype=int))
    assert len(empty) == 0 and empty.pos.shape == (0, 3)


@pytest.mark.parametrize("name,size", [("box", (0, 0, 0)), ("box", (0.1, 0.1, 0)), ("sphere", (0,)),
                                       ("cylinder", (0, 0)), ("cylinder", (0, 0.1)), ("capsule", (0, 0)),
                                       ("capsule", (0.1, 0)), ("ellipsoid", (0, 0, 0)),
                                       ("ellipsoid", (0.1, 0, 0)), ("ellipsoid", (0.1, 0.1, 0))])
def test_zero_sizes_are_finite(name, size):
    el = geom_elements(name, size, RES)
    assert len(el) > 0
    for arr in (el.pos, el.normal, el.area):
        assert np.all(np.isfinite(arr))
    np.testing.assert_allclose(np.linalg.norm(el.normal, axis=1), 1.0)
    np.testing.assert_allclose(el.area.sum(), surface_area(name, size), rtol=1e-3, atol=1e-15)


@pytest.mark.parametrize("bad", [-0.01, 0.0, float("nan"), float("inf"), -float("inf"), "abc", None])
def test_bad_resolution(bad):
    with pytest.raises(ValueError, match="resolution") as info:
        geom_elements("box", (0.1, 0.1, 0.1), bad)
    assert repr(bad) in str(info.value)


@pytest.mark.parametrize("bad", ["plane", "hfield", "sdf", "cube", 0, 1, 8, 42, mujoco.mjtGeom.mjGEOM_PLANE, None])
def test_unknown_geom_type(bad):
    for call in (lambda: geom_elements(bad, (0.1, 0.1, 0.1), RES), lambda: surface_area(bad, (0.1, 0.1, 0.1))):
        with pytest.raises(ValueError) as info:
            call()
        for name in GEOM_TYPES:
            assert name in str(info.value)


def test_int_and_enum_geom_types():
    a = geom_elements("capsule", (0.02, 0.05), RES)
    for t in (int(mujoco.mjtGeom.mjGEOM_CAPSULE), mujoco.mjtGeom.mjGEOM_CAPSULE, np.int32(3), "Capsule"):
        b = geom_elements(t, (0.02, 0.05, 0.0), RES)
        np.testing.assert_array_equal(a.pos, b.pos)


def test_bad_sizes_and_meshes():
    with pytest.raises(ValueError, match="size"):
        geom_elements("box", (0.1, 0.1), RES)
    with pytest.raises(ValueError, match="size"):
        geom_elements("sphere", (-0.1,), RES)
    with pytest.raises(ValueError, match="size"):
        geom_elements("ellipsoid", (0.1, float("nan"), 0.1), RES)
    with pytest.raises(ValueError, match="mesh"):
        geom_elements("mesh", None, RES)
    with pytest.raises(ValueError, match="mesh_faces"):
        geom_elements("mesh", None, RES, TET_V, np.array([[0, 1, 4]]))
    with pytest.raises(ValueError, match="mesh_vertices"):
        geom_elements("mesh", None, RES, TET_V[:, :2], TET_F)


def test_elements_container():
    a = geom_elements("box", (0.1, 0.1, 0.1), 0.1)
    b = geom_elements("sphere", (0.1,), 0.1)
    c = Elements.concatenate([a, b])
    assert len(c) == len(a) + len(b)
    np.testing.assert_array_equal(c.pos[len(a):], b.pos)
    assert c.total_area == pytest.approx(a.total_area + b.total_area)
    assert len(Elements.concatenate([])) == 0
    with pytest.raises(ValueError):
        Elements(np.zeros((2, 3)), np.zeros((3, 3)), np.zeros(2))
    with pytest.raises(AttributeError):
        a.area = np.zeros(6)  # frozen
    rot = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    t = a.transform(rot, [1, 2, 3])
    np.testing.assert_allclose(t.pos, a.pos @ rot.T + [1, 2, 3])
    np.testing.assert_allclose(t.normal, a.normal @ rot.T)


def _fmt(a):
    return " ".join(f"{x:g}" for x in np.ravel(a))


MJCF = f"""
<mujoco>
  <asset>
    <mesh name="cube" vertex="{_fmt(0.1 * CUBE_V)}" face="{_fmt(CUBE_F)}"/>
    <mesh name="tet" vertex="{_fmt(0.1 * TET_V)}" face="{_fmt(TET_F)}"/>
  </asset>
  <worldbody>
    <body name="b" pos="0.3 -0.2 0.5" euler="10 20 30">
      <freejoint/>
      <geom name="box" type="box" size="0.05 0.03 0.02" pos="0.1 0 0" euler="0 0 45"/>
      <geom name="sphere" type="sphere" size="0.04" pos="0 0.1 0"/>
      <geom name="capsule" type="capsule" fromto="0 0 0 0.1 0.1 0.1" size="0.02"/>
      <geom name="cylinder" type="cylinder" size="0.03 0.05" pos="-0.1 0 0" euler="90 0 0"/>
      <geom name="ellipsoid" type="ellipsoid" size="0.05 0.03 0.02" pos="0 -0.1 0" quat="0.9 0.1 0.3 0.2"/>
      <geom name="cube" type="mesh" mesh="cube" pos="0 0 0.2"/>
      <geom name="tet" type="mesh" mesh="tet" pos="0 0 -0.2" euler="0 30 0"/>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture(scope="module")
def model_and_data():
    model = mujoco.MjModel.from_xml_string(MJCF)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _world(model, data, geom_id, el):
    body = model.geom_bodyid[geom_id]
    rot = data.xmat[body].reshape(3, 3)
    return el.pos @ rot.T + data.xpos[body], el.normal @ rot.T


def test_model_covers_every_type(model_and_data):
    model, _ = model_and_data
    names = {mujoco.mjtGeom(int(t)).name[len("mjGEOM_"):].lower() for t in model.geom_type}
    assert names == set(GEOM_TYPES)


@pytest.mark.parametrize("geom", ["box", "sphere", "capsule", "cylinder", "ellipsoid", "cube", "tet"])
def test_discretize_geom_body_frame(model_and_data, geom):
    model, data = model_and_data
    gid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom)
    el = discretize_geom(model, gid, RES)
    # body frame -> world through the body pose must equal the geom-frame elements through the geom pose
    pos_w, nrm_w = _world(model, data, gid, el)
    gtype = int(model.geom_type[gid])
    kw = {}
    if geom in ("cube", "tet"):
        mid = model.geom_dataid[gid]
        va, vn = model.mesh_vertadr[mid], model.mesh_vertnum[mid]
        fa, fn = model.mesh_faceadr[mid], model.mesh_facenum[mid]
        kw = {"mesh_vertices": model.mesh_vert[va:va + vn], "mesh_faces": model.mesh_face[fa:fa + fn]}
    local = geom_elements(gtype, model.geom_size[gid], RES, **kw)
    grot = data.geom_xmat[gid].reshape(3, 3)
    np.testing.assert_allclose(pos_w, local.pos @ grot.T + data.geom_xpos[gid], atol=1e-6)
    np.testing.assert_allclose(nrm_w, local.normal @ grot.T, atol=1e-6)
    np.testing.assert_allclose(el.area, local.area)
    np.testing.assert_allclose(np.linalg.norm(el.normal, axis=1), 1.0, atol=1e-12)
    # closed surface: divergence theorem in the body frame (independent of the geom offset)
    area = el.area.sum()
    np.testing.assert_allclose(el.normal.T @ el.area, 0.0, atol=1e-6 * area)
    centre = model.geom_pos[gid]
    outward = np.einsum("ij,ij->i", el.normal, el.pos - centre)
    if geom != "tet":  # every other shape is centred on its geom origin
        assert np.all(outward > 0)


def test_discretize_mesh_undoes_mujoco_recentring(model_and_data):
    """MuJoCo moves mesh vertices to the centre of mass; the world-frame elements must still lie on the MJCF cube."""
    model, data = model_and_data
    gid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "cube")
    assert not np.allclose(model.geom_pos[gid], [0, 0, 0.2])  # MuJoCo did shift the geom
    el = discretize_geom(model, gid, 0.01)
    # in the body frame the MJCF cube is [0, 0.1]^2 x [0.2, 0.3]
    local = el.pos - np.array([0.05, 0.05, 0.25])
    np.testing.assert_allclose(np.max(np.abs(local), axis=1), 0.05, atol=1e-6)
    assert np.all(np.einsum("ij,ij->i", el.normal, local) > 0.05 - 1e-6)
    np.testing.assert_allclose(el.area.sum(), 6 * 0.01, rtol=1e-6)
    np.testing.assert_allclose(np.einsum("ij,ij,i->", el.pos, el.normal, el.area) / 3, 1e-3, rtol=1e-5)

    tid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "tet")
    tet = discretize_geom(model, tid, RES)
    np.testing.assert_allclose(tet.area.sum(), 0.01 * (1.5 + math.sqrt(3) / 2), rtol=1e-5)
    np.testing.assert_allclose(np.einsum("ij,ij,i->", tet.pos, tet.normal, tet.area) / 3, 1e-3 / 6, rtol=1e-5)
    # tetrahedron x-z rotated by 30 deg about y, at (0, 0, -0.2): the y = 0 face keeps normal -y
    on_face = np.abs(tet.pos[:, 1]) < 1e-6
    assert on_face.any()
    np.testing.assert_allclose(tet.normal[on_face], np.tile([0, -1.0, 0], (on_face.sum(), 1)), atol=1e-6)


def test_discretize_geom_errors():
    model = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><geom type="plane" size="1 1 0.1"/><geom size="0.1"/></worldbody></mujoco>')
    with pytest.raises(ValueError, match="plane") as info:
        discretize_geom(model, 0, RES)
    assert all(name in str(info.value) for name in GEOM_TYPES)
    with pytest.raises(ValueError, match="geom_id"):
        discretize_geom(model, 2, RES)
    with pytest.raises(ValueError, match="resolution"):
        discretize_geom(model, 1, -1.0)
    np.testing.assert_allclose(discretize_geom(model, 1, RES).area.sum(), 4 * math.pi * 0.01)


UNION = """<mujoco><worldbody><body name="foot">
  <geom name="a" type="box" pos="0 0 0" size="0.02 0.01 0.01"/>
  <geom name="b" type="box" pos="0.02 0 0" size="0.02 0.01 0.01"/>
  <geom name="c" type="sphere" pos="0 0 0" size="0.005"/>
  <geom name="d" type="capsule" pos="0 0.1 0" size="0.01 0.02"/>
</body><body name="other" pos="0 0 0"><geom name="e" type="box" size="0.02 0.01 0.01"/></body>
</worldbody></mujoco>"""


def test_elements_inside_other_geoms_of_the_body_are_dropped():
    m = mujoco.MjModel.from_xml_string(UNION)
    ids = list(range(m.ngeom))
    parts = [discretize_geom(m, g, 0.002) for g in ids]
    keep = exposed(m, ids, parts)
    # the two overlapping boxes: exactly the surface of their union (a 6 x 2 x 2 cm box) remains
    area = sum(parts[g].area[keep[g]].sum() for g in (0, 1))
    np.testing.assert_allclose(area, 2 * (0.06 * 0.02 * 2 + 0.02 * 0.02), rtol=1e-9)
    assert not keep[2].any()          # the sphere is buried in box a
    assert keep[3].all()              # the capsule is apart
    assert keep[4].all()              # box e overlaps box a, but belongs to another body
    # inside_geom: strictly inside only (a point on the surface is outside)
    assert inside_geom(m, 0, [[0, 0, 0], [0.02, 0, 0], [0.0199, 0, 0]]).tolist() == [True, False, True]
    assert inside_geom(m, 3, [[0, 0.1, 0.025], [0, 0.1, 0.031]]).tolist() == [True, False]




CROSS = """<mujoco><worldbody><body name="plus">
  <geom name="a" type="box" size="0.02 0.01 0.005"/>
  <geom name="b" type="box" pos="0.0013 0 0" size="0.01 0.02 0.005"/>
</body></worldbody></mujoco>"""


@pytest.mark.parametrize("res", [0.03, 0.007, 0.003])
def test_exposed_elements_trim_partly_covered_cells_exactly(res):
    """Two crossing boxes (a plus sign 4 cm across, 1 cm thick, one arm off centre by 1.3 mm so no cell
    edge meets the overlap's): the exposed area is the union's at any
    element size, not only once the cells are finer than the overlap; coplanar top and bottom faces
    count once; what is kept lies on the union's surface, outside the other box."""
    m = mujoco.MjModel.from_xml_string(CROSS)
    parts = [discretize_geom(m, g, res) for g in (0, 1)]
    out = exposed_elements(m, [0, 1], parts, res)
    plus = 0.04 * 0.02 * 2 - 0.02 * 0.02
    union = 2 * plus + 0.16 * 0.01  # top and bottom, and the 16 cm outline x 1 cm
    np.testing.assert_allclose(sum(e.area.sum() for e in out), union, rtol=1e-12)
    for k, e in enumerate(out):
        assert np.all(e.area > 0) and not inside_geom(m, 1 - k, e.pos).any()
    # the centroid rule of `exposed` gets it only when cells resolve the overlap
    keep = exposed(m, [0, 1], parts)
    centroid_rule = sum(p.area[k].sum() for p, k in zip(parts, keep))
    assert abs(centroid_rule - union) > 0.01 * union


def test_box_chain_leg_has_its_union_area_at_every_resolution():
    """The hexapod's C-leg as 8 boxes, lengthened so the convex-side corners meet: the grains see the
    mitred chain's surface (convex side sum L_i w, concave side shorter by 2 x the lengthenings, the two
    side faces 2 t x the centre line, the two end caps) from 20 mm down to 1.25 mm elements."""
    from mjrft.geometry.curved_leg import curved_leg_boxes
    from mjrft.models import hexapod_model
    m = hexapod_model()
    body = m.body("leg_lf").id
    ids = [g for g in range(m.ngeom) if m.geom_bodyid[g] == body]
    boxes = curved_leg_boxes(0.041, 1 / 0.0205, 0.01, 0.003, 8)
    t, w = 0.003, 0.01
    length = np.array([2 * b["size"][2] for b in boxes])
    ext = 0.5 * t * math.tan(abs(1 / 0.0205) * (math.pi * 0.0205 / 8) / 2)
    lengthened = np.full(8, 2 * ext)
    lengthened[[0, -1]] = ext
    expected = w * length.sum() + w * (length - 2 * lengthened).sum() + 2 * t * (length - lengthened).sum() + 2 * w * t
    for res in (0.02, 0.005, 0.0025, 0.00125):
        parts = [discretize_geom(m, g, res) for g in ids]
        area = sum(e.area.sum() for e in exposed_elements(m, ids, parts, res))
        np.testing.assert_allclose(area, expected, rtol=1e-9)
