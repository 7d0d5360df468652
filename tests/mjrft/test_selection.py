"""Which geoms feel the grains (mjrft.selection): by default the collision geoms of the moving bodies, a named body's
collision geoms, a named geom even when visual-only; the world body and an empty selection are refused."""

from __future__ import annotations

import mujoco
import pytest

import mjrft
from mjrft.selection import select_geoms

SCENE = """<mujoco><worldbody><geom name="floor" type="plane" size="1 1 .1"/>
<body name="foot" pos="0 0 .1"><freejoint/><geom name="sole" type="box" size=".02 .02 .005"/>
  <geom name="shell" type="sphere" size=".03" contype="0" conaffinity="0"/>
  <body name="toe" pos=".04 0 0"><joint type="hinge"/><geom name="tip" type="capsule" size=".005 .01"/></body>
</body></worldbody></mujoco>"""


def test_the_default_and_named_selections():
    m = mujoco.MjModel.from_xml_string(SCENE)
    sole, shell, tip = (m.geom(n).id for n in ("sole", "shell", "tip"))
    assert select_geoms(m, None, None) == [sole, tip]  # not the floor (world body), not the visual-only shell
    assert select_geoms(m, ["foot"], None) == [sole] and select_geoms(m, "foot toe", None) == [sole, tip]
    assert select_geoms(m, None, ["shell"]) == [shell]  # a named geom is taken even when visual-only
    assert select_geoms(m, ["toe"], ["sole"]) == [sole, tip]
    with pytest.raises(ValueError, match="bodies names the world body"):
        select_geoms(m, ["world"], None)
    with pytest.raises(ValueError, match="unknown body 'heel'.*foot"):
        select_geoms(m, ["heel"], None)


def test_empty_body_or_geom_selection_is_an_error():
    from mjrft.models import hexapod_model

    m = hexapod_model()
    for kw in ({"bodies": []}, {"geoms": ()}):
        with pytest.raises(ValueError, match=r"=\[\] selects nothing"):
            mjrft.GranularTerrain(m, **kw)
