"""The free surface (mjrft.surface): a flat surface's height everywhere, a height field's heights at its nodes,
bilinear between them, continued beyond its border, and turned with its geom's yaw."""

from __future__ import annotations

import math

import numpy as np

from mjrft.surface import surface_height, surface_heights

NO_FIELD = np.zeros((0, 0))
NO_FRAME = np.zeros(8)
# 3 rows x 4 columns of world heights; the field spans x in [-0.3, 0.3], y in [-0.1, 0.1] about its centre
HF_Z = np.array([[0.00, 0.01, 0.02, 0.03],
                 [0.10, 0.11, 0.12, 0.13],
                 [0.20, 0.21, 0.22, 0.23]])
RX, RY = 0.3, 0.1
CELL_X, CELL_Y = 2 * RX / 3, 2 * RY / 2


def frame(x=0.0, y=0.0, yaw=0.0):
    return np.array([x, y, math.cos(yaw), math.sin(yaw), RX, RY, 1 / CELL_X, 1 / CELL_Y])


def test_a_flat_surface_has_its_height_everywhere():
    for px, py in ((0.0, 0.0), (12.5, -3.0)):
        assert surface_height(px, py, 0.04, NO_FIELD, NO_FRAME) == 0.04


def test_a_height_field_is_its_nodes_bilinear_between_and_continued_beyond():
    f = frame(x=1.0, y=2.0)
    for j in range(3):
        for i in range(4):
            px, py = 1.0 - RX + i * CELL_X, 2.0 - RY + j * CELL_Y
            assert math.isclose(surface_height(px, py, 0.04, HF_Z, f), HF_Z[j, i], abs_tol=1e-12)
    # the middle of the first cell: the mean of its four nodes (a nearest-node lookup would give one of them)
    mid = surface_height(1.0 - RX + CELL_X / 2, 2.0 - RY + CELL_Y / 2, 0.04, HF_Z, f)
    assert math.isclose(mid, HF_Z[:2, :2].mean(), abs_tol=1e-12)
    assert math.isclose(surface_height(5.0, 2.0 + RY, 0.04, HF_Z, f), HF_Z[2, 3], abs_tol=1e-12)  # clamped
    # a quarter turn: the field's +x axis lies along world +y
    turned = frame(yaw=math.pi / 2)
    assert math.isclose(surface_height(0.0, RX, 0.04, HF_Z, turned), HF_Z[1, 3], abs_tol=1e-12)
    assert math.isclose(surface_height(RX, 0.0, 0.04, HF_Z, turned), HF_Z[0, 1] + 0.5 * (HF_Z[0, 2] - HF_Z[0, 1]),
                        abs_tol=1e-12)


def test_many_points_give_what_one_point_gives():
    rng = np.random.default_rng(0)
    xs, ys = rng.uniform(-0.5, 0.5, 50), rng.uniform(-0.2, 0.2, 50)
    out = np.empty(50)
    surface_heights(xs, ys, 0.04, HF_Z, frame(yaw=0.3), out)
    assert np.array_equal(out, [surface_height(x, y, 0.04, HF_Z, frame(yaw=0.3)) for x, y in zip(xs, ys)])
    assert np.ptp(out) > 0.05
