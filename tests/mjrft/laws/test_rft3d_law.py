"""3D-RFT never pulls on a face; the plane of motion is the motion's own beyond 10 degrees off vertical."""

import math

import numpy as np
import pytest

from mjrft import laws
from mjrft.laws.common import PLANE_EPS, PLANE_FADE, motion_plane
from mjrft.laws.rft import rft_stress, rft_stress_batch
from mjrft.media import get_medium
from mjrft.laws.registry import parameter_vector


def _unit(a):
    a = np.asarray(a, float)
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _sweep_normals_and_motions():
    """Random directions plus the axes, the diagonals and faces the motion slides along exactly."""
    rng = np.random.default_rng(7)
    n = _unit(rng.normal(size=(20000, 3)))
    v = rng.normal(size=(20000, 3)) * rng.choice([1e-9, 1.0, 1e3], size=(20000, 1))
    axes = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1), (1, 1, 0), (1, 0, 1), (1, 0, -1),
            (0, 1, 1), (1, 1, 1), (1, -1, -1)]
    grid = _unit(np.array(axes, float))
    gn, gv = np.repeat(grid, len(grid), axis=0), np.tile(grid, (len(grid), 1))
    # faces that the motion slides along: v perpendicular to n (lead weight 1/2)
    t = _unit(np.cross(n[:2000], rng.normal(size=(2000, 3))))
    return np.vstack([n, gn, n[:2000]]), np.vstack([v, gv, t])


@pytest.mark.parametrize("medium", ["poppy_cp", "glass3_cp", "generic"])
@pytest.mark.parametrize("depth", [1e-6, 0.05, 10.0])
def test_rft3d_never_pulls_on_a_face(medium, depth):
    n, v = _sweep_normals_and_motions()
    f = laws.rft3d(depth, n, v, 1e-4, medium)
    assert np.all(np.isfinite(f))
    fn = np.einsum("ij,ij->i", f, n)
    scale = np.abs(f).max()
    assert scale > 0
    assert fn.max() <= 1e-12 * scale, f"force along the outward normal: {fn.max()!r} N"
    # the compressive faces still carry load: the sweep is not trivially zero
    assert (fn < -1e-6 * scale).mean() > 0.3


def test_rft3d_top_face_of_a_dragged_plate_feels_nothing_and_bottom_face_keeps_its_load():
    # alpha_gen of the generic fit is 0.110 up on both faces of a horizontal plate dragged edgewise: along the
    # top face's outward normal (tension, clamped) and against the bottom face's (compression, kept)
    v = np.array([[1.0, 0.0, 0.0]])
    top = laws.rft3d(0.05, [[0, 0, 1.0]], v, 1e-4, "poppy_cp")
    bottom = laws.rft3d(0.05, [[0, 0, -1.0]], v, 1e-4, "poppy_cp")
    assert np.all(top == 0.0)
    gen = laws.rft3d_alpha_generic([[0, 0, -1.0]], v)[0]
    assert gen[2] == pytest.approx(0.110, abs=5e-4)
    med = get_medium("poppy_cp")
    # lead weight 1/2 (the motion runs along the face), stress xi_n alpha depth
    assert bottom[0, 2] == pytest.approx(0.5 * med.xi_n * gen[2] * 0.05 * 1e-4, rel=1e-9)


def test_rft3d_force_is_continuous_where_the_normal_part_changes_sign():
    # tilt a face from the top of a horizontally dragged plate (tensile, clamped) towards facing the motion
    a = np.linspace(0.0, 0.5 * math.pi, 20001)
    n = np.column_stack([np.sin(a), np.zeros_like(a), np.cos(a)])
    f = laws.rft3d(0.05, n, [[1.0, 0.0, 0.0]], 1e-4, "poppy_cp")
    step = np.abs(np.diff(f, axis=0)).max()
    assert step < 2e-3 * np.abs(f).max()


@pytest.mark.parametrize("tilt_deg", [10.0, 30.0, 60.0, 90.0])
def test_motion_plane_is_the_motions_own_beyond_ten_degrees_off_vertical(tilt_deg):
    s = math.sin(math.radians(tilt_deg))
    rng = np.random.default_rng(1)
    for _ in range(200):
        nx, ny = rng.normal(size=2)
        phi = rng.uniform(0, 2 * math.pi)
        mx, my = s * math.cos(phi), s * math.sin(phi)
        rx, ry = motion_plane(nx, ny, mx, my)
        assert (rx, ry) == pytest.approx((math.cos(phi), math.sin(phi)), abs=1e-15)


def test_motion_plane_turns_to_the_normal_near_vertical_motion_continuously():
    nx, ny = 0.0, 1.0
    assert motion_plane(nx, ny, 0.0, 0.0) == pytest.approx((0.0, 1.0))
    assert motion_plane(0.0, 0.0, 0.0, 0.0) == (1.0, 0.0)
    # motion tilted along +x by angles from 0 to 15 deg: r turns from the normal (+y) to the motion (+x), smoothly
    t = np.linspace(0.0, math.radians(15.0), 3001)
    r = np.array([motion_plane(nx, ny, math.sin(a), 0.0) for a in t])
    ang = np.arctan2(r[:, 1], r[:, 0])
    assert ang[0] == pytest.approx(0.5 * math.pi)
    assert np.all(np.diff(ang) <= 1e-15)  # monotone
    assert np.abs(np.diff(ang)).max() < 0.01
    assert ang[np.sin(t) >= PLANE_FADE].max() == 0.0
    assert PLANE_EPS < PLANE_FADE


def test_rft_batch_equals_scalar_across_the_plane_fade():
    rng = np.random.default_rng(3)
    count = 4000
    n = _unit(rng.normal(size=(count, 3))).T.copy()
    tilt = rng.uniform(0.0, math.radians(20.0), count)  # motion from vertical to 20 deg off, across the fade
    phi = rng.uniform(0, 2 * math.pi, count)
    sgn = rng.choice([-1.0, 1.0], count)
    m = np.array([np.sin(tilt) * np.cos(phi), np.sin(tilt) * np.sin(phi), sgn * np.cos(tilt)])
    depth = rng.uniform(0.001, 0.1, count)
    p = parameter_vector(get_medium("poppy_cp"))
    out = np.zeros((3, count))
    rft_stress_batch(count, depth, n, m, p, out)
    ref = np.array([rft_stress(depth[i], *n[:, i], *m[:, i], 0.01, p) for i in range(count)]).T
    assert np.allclose(out, ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())
