"""The ``shoal`` scene: dry sand, then saturated sand, then shallow water over saturated sand.

Strips along x (the hexapod starts at x = 0 and walks toward +x; :class:`mjrft.GranularTerrain`
regions, carried in the MJCF ``<custom>`` section):

=================  ==================  =======  ===========  ===========================================
x (m)              medium              law      water (m)    what
=================  ==================  =======  ===========  ===========================================
x < 0.5            ``poppy_cp``        ``rft``  0            dry grains (mjrft's reference medium)
0.5 <= x < 1.0     ``sea_sand_...``    ``wet``  0            saturated sea sand (SGRFT), water table at
                                                             the surface
x >= 1.0           ``sea_sand_...``    ``wet``  0.02         2 cm of standing water over saturated sand
=================  ==================  =======  ===========  ===========================================

(``sea_sand_...`` = ``sea_sand_saturated``.) Choices: the catalogue has no dry sea sand (the paper's dry
reference is :func:`mjrft.laws.wet.dry_reference`, not a catalogue name an MJCF file can carry), so the
dry strip is closely packed poppy seeds, whose zeta (0.488 N/cm^3) is within 13 % of that reference
(0.432 N/cm^3). 2 cm of water reaches half-way up the RHex-class legs (4.1 cm chord) and stays below
the belly (~4 cm up). Buoyancy is on (water and saturated sand); neighbouring strips blend over the
coupler's default 1 cm transition. The bed runs from x = -0.5 to 2.5 m. The strips are placed for
the open-loop tripod at 2 Hz, which walks about 22 cm/s here, so it reaches the saturated sand after
~2 s and the water after ~4.5 s; a 10 s episode crosses all three.
"""

from __future__ import annotations

import mujoco

from .hexapod import hexapod_xml

#: keyword arguments of :func:`mjrft.models.hexapod_xml` that make the shoal scene
SHOAL = {
    "medium": "poppy_cp",
    "law": "rft",
    "regions": [(0.5, "sea_sand_saturated", "wet", 0.0), (1.0, "sea_sand_saturated", "wet", 0.02)],
    "buoyancy": True,
    "bed_length": 3.0,
}


def hexapod_shoal_xml(curvature: float | None = None, variant: str = "rhex", **kw) -> str:
    """MJCF text of the hexapod on the shoal (keyword arguments as :func:`mjrft.models.hexapod_xml`; they
    override the scene's, e.g. ``regions=...``)."""
    return hexapod_xml(curvature, variant=variant, sand=True, **{**SHOAL, **kw})


def hexapod_shoal_model(curvature: float | None = None, variant: str = "rhex", **kw) -> mujoco.MjModel:
    """Compiled :class:`mujoco.MjModel` of :func:`hexapod_shoal_xml`."""
    return mujoco.MjModel.from_xml_string(hexapod_shoal_xml(curvature, variant=variant, **kw))
