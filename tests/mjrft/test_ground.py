"""The ground memory (mjrft.ground): off by default and free, footprints and ridges, conservation of the grains,
slopes at the angle of repose, the packing under shear and load, the force it gives, and the extremes. Each check is
paired with a control that fails it."""

from __future__ import annotations

import math
import warnings

import mujoco
import numpy as np
import pytest

import mjrft
from mjrft import GranularTerrain
from mjrft import ground
from mjrft.ground import C_H, C_PEND, C_PHI, C_SUB, DEEPEN_TOL, GroundOptions, ground_volumes, packing_of

FOOT = """<mujoco><option timestep="0.001"/><worldbody>
<body name="foot"><joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
<geom type="box" size="{hx} {hy} {hz}" mass="0.1"/></body></worldbody></mujoco>"""
HFIELD_FOOT = """<mujoco><asset><hfield name="hf" nrow="2" ncol="2" size="0.3 0.2 0.01 0.1" elevation="0 1 0 1"/>
</asset><worldbody><geom name="ground" type="hfield" hfield="hf" contype="0" conaffinity="0"/>
<body name="foot" pos="0 0 0.02"><freejoint/><geom type="box" size="0.02 0.02 0.005" mass="0.1"/></body>
</worldbody></mujoco>"""
CELL = 0.005
EXTENT = (-0.12, 0.12, -0.08, 0.08)


def rig(medium="poppy_cp", size=(0.02, 0.02, 0.005), memory=True, **options):
    """(model, data, terrain) of a box foot moved kinematically along x and z over a small grid of 5 mm cells that
    updates at every call."""
    m = mujoco.MjModel.from_xml_string(FOOT.format(hx=size[0], hy=size[1], hz=size[2]))
    d = mujoco.MjData(m)
    opts = dict(cell=CELL, extent=EXTENT, period=1e-6)
    opts.update(options)
    t = GranularTerrain(m, medium, "rft", resolution=0.005, ground_memory=GroundOptions(**opts) if memory else False)
    return m, d, t


def move(m, d, t, xs, zs, speed=0.01, step=5e-4):
    """Move the foot's centre through the points (xs, zs) (m) at ``speed`` (m/s) in samples ``step`` apart; returns
    the vertical granular force (N) at each sample."""
    xs, zs = np.broadcast_arrays(np.asarray(xs, float), np.asarray(zs, float))
    path = np.stack([xs, zs], 1)
    pts = [path[0]]
    for a, b in zip(path[:-1], path[1:]):
        n = max(1, int(math.ceil(np.linalg.norm(b - a) / step)))
        pts += [a + (b - a) * (k + 1) / n for k in range(n)]
    pts = np.array(pts)
    fz = []
    warnings.simplefilter("ignore")  # a kinematic rig: the stability checks' timestep is the sampling's
    for k in range(len(pts)):
        v = (pts[min(k + 1, len(pts) - 1)] - pts[max(k - 1, 0)])
        nv = np.linalg.norm(v)
        d.qpos[:] = pts[k]
        d.qvel[:] = v / nv * speed if nv > 0 else 0.0
        mujoco.mj_fwdPosition(m, d)
        mujoco.mj_fwdVelocity(m, d)
        d.time += step / speed
        fz.append(t.compute(d, step / speed)[1, 2])
    return np.array(fz)


def press(m, d, t, depth, x=0.0, hz=0.005, speed=0.01):
    """Press the foot straight down from above the surface until its bottom is ``depth`` deep, then lift it out;
    returns the vertical force on the way down."""
    top = 0.02 + hz
    down = move(m, d, t, [x, x], [top, hz - depth], speed)
    move(m, d, t, [x, x], [hz - depth, top], speed)
    return down


def slopes(t) -> np.ndarray:
    """The steepest drop between neighbouring cells of the grains' surface, per cell edge (tan of the slope)."""
    h = t.terrain_state.g_height
    c = t.terrain_model.ground.frame[2]
    return np.maximum(np.abs(np.diff(h, axis=0)).max(), np.abs(np.diff(h, axis=1)).max()) / c


# ------------------------------------------------------------------------------------------------
# off by default, and free
# ------------------------------------------------------------------------------------------------
def test_off_by_default_with_empty_records():
    m, d, t = rig(memory=False)
    assert not t.ground_memory and not t.terrain_model.ground.on
    assert t.terrain_state.g_cells.size == 0 and t.terrain_state.g_elem.size == 0
    assert t.terrain_state.scr_f.shape[0] == 13
    assert np.array_equal(t.ground_height([0.0, 0.1], 0.0), t.surface_height([0.0, 0.1], 0.0))


def test_prepared_ground_gives_the_forces_of_no_memory_bit_for_bit():
    """Until a footprint changes it, a cell as prepared reads the undisturbed surface and the medium's own row: the
    first steps of a memory give exactly the forces without one. Control: the same comparison after the foot left a
    footprint (the second press) differs."""
    out = {}
    for memory in (False, True):
        m, d, t = rig(memory=memory, period=1e3)  # no update during the first press
        first = move(m, d, t, [0.0, 0.0], [0.025, -0.005])
        out[memory] = (first, t.force.copy())
    assert np.array_equal(out[False][0], out[True][0]) and np.array_equal(out[False][1], out[True][1])
    fz = {}
    for memory in (False, True):
        m, d, t = rig(memory=memory)
        press(m, d, t, 0.01)
        fz[memory] = press(m, d, t, 0.01)
    assert not np.array_equal(fz[False], fz[True])


# ------------------------------------------------------------------------------------------------
# footprints, ridges, conservation, repose
# ------------------------------------------------------------------------------------------------
def test_footprint_ridge_and_conservation_of_the_grains():
    """A 4 x 4 cm foot pressed 1 cm into closely packed poppy seeds and lifted leaves a hole under it and a ridge
    around it, and the grains' solid volume in the grid is what it was (to rounding). Control: the same map without
    its ridge (the displaced grains lost) fails the conservation check."""
    m, d, t = rig()
    gt, st = t.terrain_model.ground, t.terrain_state
    solid0, _ = ground_volumes(gt, st)
    press(m, d, t, 0.01)
    assert t.ground_height(0.0, 0.0) < -0.005
    ring = t.ground_height(0.035 * np.cos(np.linspace(0, 2 * np.pi, 16)), 0.035 * np.sin(np.linspace(0, 2 * np.pi, 16)))
    assert ring.max() > 0.001
    solid1, _ = ground_volumes(gt, st)
    assert abs(solid1 - solid0) <= 1e-12 * solid0
    cells = st.g_cells.copy()
    cells[:, :, C_H] = np.minimum(cells[:, :, C_H], 0.0)
    lost = st._replace(g_cells=cells)
    assert abs(ground_volumes(gt, lost)[0] - solid0) > 1e-3 * solid0


def test_slow_deepening_adds_up_past_the_tolerance():
    """A foot lowered 0.5 mm into the grains in 25,000 updates, each deepening it by 0.4 of the footprints' tolerance
    (mjrft.ground.DEEPEN_TOL: below it an update leaves the difference for later), displaces what a fast press to
    the same depth does: every footprint cell has taken the bodies' volume in it to within the tolerance, the same
    footprint depth. Control: the same map with the cells' taken volume forgotten (what dropping each update's
    sub-tolerance deepening would leave) fails the check."""
    tol = DEEPEN_TOL * CELL
    taken = {}
    for step in (0.4 * tol, 5e-4):
        m, d, t = rig()
        move(m, d, t, [0.0, 0.0], [0.03, 0.005], speed=0.01)  # down to the surface
        move(m, d, t, [0.0, 0.0], [0.005, 0.0045], speed=1e-4, step=step)
        c = t.terrain_state.g_cells
        under = c[:, :, C_SUB] > 0.0
        taken[step] = (c[:, :, C_SUB][under] / CELL ** 2, c[:, :, C_PEND][under], float(t.ground_height(0.0, 0.0)))
    sub, pend, depth = taken[0.4 * tol]
    assert sub.size == 64 and np.all(sub - pend <= tol) and np.all(pend <= sub + 1e-15)
    assert np.allclose(pend, taken[5e-4][1], rtol=0.0, atol=tol) and abs(depth - taken[5e-4][2]) <= tol
    assert abs(depth + 0.0005) <= tol
    forgotten = np.zeros_like(pend)
    assert not np.all(sub - forgotten <= tol)


def test_bulk_volume_conserved_without_a_packing_change():
    """A medium with one state (the generic profile, angle of repose given): the grains' bulk volume above the
    undisturbed surface stays 0 through a press and a drag (displaced volume conserved exactly). Control: the same
    run on poppy seeds, whose packing changes, does not keep it."""
    bulk = {}
    for medium, kw in (("generic", {"repose_angle": 30.0}), ("poppy_cp", {})):
        m, d, t = rig(medium, **kw)
        press(m, d, t, 0.01)
        move(m, d, t, [-0.04, 0.04], [0.0, 0.0], speed=0.02)
        bulk[medium] = ground_volumes(t.terrain_model.ground, t.terrain_state)[1]
    assert abs(bulk["generic"]) < 1e-12
    assert abs(bulk["poppy_cp"]) > 1e-8


def test_slopes_relax_to_the_angle_of_repose():
    """After a 2 cm deep footprint has had time to avalanche, no slope between cells exceeds the angle of repose of
    closely packed poppy seeds (47 deg, Li 2013 table S1) by more than the relaxation's tolerance, and the pit's
    walls stand near it (the grains stop at the angle, they do not level the pit). Control: the same footprint as a
    vertical-walled pit fails the first check."""
    m, d, t = rig()
    press(m, d, t, 0.02)
    for _ in range(100):  # the foot above the bed, time passing
        move(m, d, t, [0.0, 0.0], [0.05, 0.05])
    tan_lp, tan_cp = math.tan(math.radians(36.0)), math.tan(math.radians(47.0))
    relaxed = slopes(t)
    assert relaxed <= tan_cp * (1 + 1e-3) + 2e-4
    assert relaxed >= 0.8 * tan_lp
    assert t.ground_height(0.0, 0.0) < -0.005
    pit = t.terrain_state._replace(g_height=np.where(
        (np.abs(t.terrain_model.ground.frame[0] + (np.arange(t.terrain_state.g_height.shape[1]) + 0.5) * CELL)
         < 0.02)[None, :] * np.ones_like(t.terrain_state.g_height, dtype=bool), -0.02, 0.0))
    assert slopes(_Probe(t, pit)) > tan_cp * 1.2


class _Probe:
    """A terrain's model with another state (the control's map)."""

    def __init__(self, t, st):
        self.terrain_model, self.terrain_state = t.terrain_model, st


# ------------------------------------------------------------------------------------------------
# packing: shear to the critical state, load compacts loose grains; the force reads it
# ------------------------------------------------------------------------------------------------
def test_shear_dilates_close_grains_and_load_compacts_loose_ones():
    """A plate dragged through closely packed poppy seeds leaves its path looser (toward the critical state 0.60,
    the thesis sec. 1.3.3), a foot pressed into loosely packed ones leaves the grains under it closer (toward 0.62).
    Controls: each state's opposite does not move that way (the loose bed is not loosened by the press, the close
    bed not compacted by the drag)."""
    m, d, t = rig("poppy_cp", size=(0.003, 0.02, 0.02))
    move(m, d, t, [-0.05, -0.05, 0.05], [0.05, 0.0, 0.0], speed=0.02)
    path = t.ground_packing(np.linspace(-0.02, 0.02, 9), 0.0)
    assert path.max() < 0.62 - 1e-3 and path.min() >= 0.60 - 1e-9
    m, d, t = rig("poppy_lp")
    press(m, d, t, 0.015)
    under = t.ground_packing(0.0, 0.0)
    assert under > 0.58 + 1e-3 and under <= 0.62 + 1e-9
    assert not under < 0.58 and not path.max() > 0.62


def test_force_reads_the_local_packing():
    """A foot pressed into a bed whose cells were set to the loose state reads poppy_lp's row: the force is that of a
    terrain on poppy_lp without memory (to rounding), about half the closely packed one. Control: the closely packed
    bed's force is not that."""
    m, d, t = rig("poppy_cp", period=1e3)
    move(m, d, t, [0.0, 0.0], [0.05, 0.05])  # bound to its data (binding resets the ground)
    t.terrain_state.g_cells[:, :, C_PHI] = 0.58
    loose = move(m, d, t, [0.0, 0.0], [0.02, -0.01])
    m2, d2, ref = rig("poppy_lp", memory=False)
    lp = move(m2, d2, ref, [0.0, 0.0], [0.02, -0.01])
    m3, d3, cp = rig("poppy_cp", memory=False)
    close = move(m3, d3, cp, [0.0, 0.0], [0.02, -0.01])
    np.testing.assert_allclose(loose[-1], lp[-1], rtol=1e-9)
    assert abs(close[-1] / lp[-1] - 1) > 0.5


def test_reentering_a_footprint_meets_less_force():
    """The same foot pressed again into its own footprint carries less at the same depth (its depth is measured from
    the hole, and the sheared grains are looser): the disturbed ground of the DynaRoACH paper (sec. 2.2.4) and the
    thesis (sec. 1.4.2). Control: without the memory both presses give the same force."""
    peak = {}
    for memory in (False, True):
        m, d, t = rig(memory=memory)
        a = press(m, d, t, 0.01)
        b = press(m, d, t, 0.01)
        peak[memory] = b.max() / a.max()
    assert peak[True] < 0.7
    assert abs(peak[False] - 1.0) < 1e-6


# ------------------------------------------------------------------------------------------------
# API: sampling, reset, settings
# ------------------------------------------------------------------------------------------------
def test_ground_readers_broadcast_and_reset_restores_the_bed():
    m, d, t = rig()
    press(m, d, t, 0.01)
    x, y = np.meshgrid(np.linspace(-0.05, 0.05, 7), np.linspace(-0.03, 0.03, 5))
    assert t.ground_height(x, y).shape == (5, 7) and t.ground_packing(x, 0.0).shape == (5, 7)
    assert t.ground_height(0.0, 0.0).shape == ()
    t.reset()
    assert np.all(t.terrain_state.g_cells[:, :, C_H] == 0.0) and np.all(t.terrain_state.g_phi == 0.62)
    assert np.all(t.ground_height(x, y) == 0.0)


def test_packing_pairs_and_bad_settings():
    p = packing_of("poppy_cp")
    assert (p.loose.name, p.close.name, p.phi_lp, p.phi_cp, p.phi_crit) == ("poppy_lp", "poppy_cp", 0.58, 0.62, 0.60)
    g3 = packing_of("glass3_cp")
    assert g3.phi_lp == 0.61 and abs(g3.loose.zeta / g3.close.zeta - math.exp(-16.57 * 0.02)) < 1e-3
    assert not packing_of("generic", 30.0).paired
    with pytest.raises(ValueError, match="angle of repose"):
        packing_of("generic")
    for bad in (dict(cell=-1.0), dict(layer=0.0), dict(repose_angle=95.0), dict(extent=(1, 0, 0, 1))):
        with pytest.raises(ValueError):
            GroundOptions(**bad)
    with pytest.raises(TypeError, match="ground_memory"):
        GroundOptions.from_value("yes")
    m = mujoco.MjModel.from_xml_string(FOOT.format(hx=0.02, hy=0.02, hz=0.005))
    with pytest.raises(ValueError, match="MAX_GROUND_CELLS"):
        GranularTerrain(m, "poppy_cp", ground_memory=GroundOptions(cell=1e-4, extent=(-1, 1, -1, 1)))



def test_the_jax_path_takes_the_ground_memory_on_either_pass():
    """The direct pass and the general pass (here the inertial regime) carry the memory; ``cull`` is refused with it,
    and so is a world's own height field (the memory keeps the undisturbed surface under its cells)."""
    pytest.importorskip("jax")
    from mjrft.mjx import Sand

    m = mujoco.MjModel.from_xml_string(FOOT.format(hx=0.02, hy=0.02, hz=0.005))
    assert Sand.from_model(m, GranularTerrain(m, "poppy_cp", ground_memory=True).terrain_model).ground is not None
    assert Sand.from_model(m, GranularTerrain(m, "poppy_cp").terrain_model).ground is None
    general = Sand.from_model(m, GranularTerrain(m, "poppy_cp", inertial=True, ground_memory=True).terrain_model)
    assert general.general and general.ground is not None
    with pytest.raises(NotImplementedError, match="cull"):
        Sand.from_model(m, GranularTerrain(m, "poppy_cp", ground_memory=True).terrain_model, cull=10)
    hf = mujoco.MjModel.from_xml_string(HFIELD_FOOT)
    sand = Sand.from_model(hf, GranularTerrain(hf, "poppy_cp", surface="ground", ground_memory=True).terrain_model)
    assert sand.hfield and sand.ground is not None and sand.init().ground is not None
    with pytest.raises(ValueError, match="height field"):
        sand.init(surface=sand.surface_init + 0.01)


def test_envs_pass_the_keyword_through():
    from mjrft.envs.hexapod import HexapodSand

    env = HexapodSand(ground_memory=True)
    assert env.terrain.ground_memory
    env.reset(seed=0)
    for _ in range(20):
        env.step(env.action_space.sample())
    assert np.any(env.terrain.terrain_state.g_height != 0.0)
    env.reset(seed=1)
    assert np.all(env.terrain.terrain_state.g_height == 0.0)
    env.close()
    assert not HexapodSand().terrain.ground_memory


# ------------------------------------------------------------------------------------------------
# the extremes (benchmarks/ground_extremes.py runs them for minutes and writes its report)
# ------------------------------------------------------------------------------------------------
def _standing_creep(memory: bool, loosen: bool = False) -> float:
    """How far (m) the hexapod, standing at its initial pose on poppy_cp, sinks between 1 s and 3 s; with the memory
    the grains' volume is asserted conserved. ``loosen``: its bed set to the loose state at 1 s (the control)."""
    model = mujoco.MjModel.from_xml_path(mjrft.models.model_path("hexapod"))
    data = mujoco.MjData(model)
    t = GranularTerrain(model, ground_memory=memory)
    t.bind(data)
    solid0 = ground_volumes(t.terrain_model.ground, t.terrain_state)[0] if memory else 0.0
    data.ctrl[:] = 0.0
    t.step(data, 1000)
    z1 = data.qpos[2]
    if loosen:
        t.terrain_state.g_cells[:, :, C_PHI] = 0.58
        t.terrain_state.g_group[:] = -1.0  # every element reads the ground afresh
        solid0 = ground_volumes(t.terrain_model.ground, t.terrain_state)[0]
    t.step(data, 2000)
    if memory:
        assert abs(ground_volumes(t.terrain_model.ground, t.terrain_state)[0] - solid0) <= 1e-12 * solid0
    return z1 - data.qpos[2]


def test_a_standing_robot_does_not_creep_on_the_memory():
    """Standing for 2 s after settling, the hexapod sinks at most 0.5 mm more with the memory than without (its feet
    at yield creep and dilate the grains they move through: 0.2 mm; benchmarks/ground_extremes.py shows it stop),
    and the grains' volume stays (asserted inside). Control: the same robot whose bed is loosened under it sinks
    further (more than 1 mm: the check sees a weaker ground)."""
    off, on = _standing_creep(False), _standing_creep(True)
    assert on - off < 5e-4
    assert _standing_creep(True, loosen=True) - off > 1e-3


def _packing_and_conservation(t, solid0) -> bool:
    gt, st = t.terrain_model.ground, t.terrain_state
    ok_phi = st.g_phi.min() >= gt.pack[0] - 1e-12 and st.g_phi.max() <= gt.pack[1] + 1e-12
    return bool(ok_phi and abs(ground_volumes(gt, st)[0] - solid0) <= 1e-12 * solid0
                and np.all(np.isfinite(st.g_cells)) and np.abs(st.g_height).max() < 0.03)


def test_12hz_strides_keep_the_ground_bounded_and_conserved():
    """The DynaRoACH-sized hexapod turning its tripods at 12 Hz on 3 mm glass for 0.5 s: forces finite, every cell's
    packing between the two states, the surface within 3 cm, the grains' volume conserved. Control: the same check
    rejects the map with one cell's packing pushed past the closely packed state."""
    from mjrft.models.hexapod import TRIPOD_A, hexapod_xml

    model = mujoco.MjModel.from_xml_string(hexapod_xml(variant="small", medium="glass3_cp", law="rft",
                                                       resolution=0.005))
    data = mujoco.MjData(model)
    t = GranularTerrain(model, ground_memory=True)
    t.bind(data)
    solid0 = ground_volumes(t.terrain_model.ground, t.terrain_state)[0]
    legs_a = {f"leg_{k}" for k in TRIPOD_A}
    off = np.array([0.0 if model.body(int(model.jnt_bodyid[model.actuator_trnid[i, 0]])).name in legs_a else math.pi
                    for i in range(model.nu)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(500):
            data.ctrl[:] = 2 * math.pi * 12.0 * data.time + off
            t.step(data, 1)
    assert np.all(np.isfinite(t.force)) and np.any(t.terrain_state.g_height != 0.0)
    assert _packing_and_conservation(t, solid0)
    t.terrain_state.g_cells[5, 5, C_PHI] = 0.64
    assert not _packing_and_conservation(t, solid0)


def test_deep_trench_relaxes_and_conserves():
    """A plate pushed 6 cm deep (twice the packing's layer), dragged 5 cm and lifted, then left at rest: the grains'
    volume is conserved, the packing stays between the states and every slope is at the angle of repose or below
    (the control of that check: test_slopes_relax_to_the_angle_of_repose's vertical pit)."""
    m, d, t = rig(period=4e-3)
    solid0 = ground_volumes(t.terrain_model.ground, t.terrain_state)[0]
    move(m, d, t, [0.0, 0.0, 0.05, 0.05], [0.03, -0.055, -0.055, 0.03], speed=0.05)
    for _ in range(150):
        move(m, d, t, [0.05, 0.05], [0.06, 0.06], speed=0.05, step=2e-4)
    assert t.ground_height(0.025, 0.0) < -1e-3
    assert _packing_and_conservation(t, solid0)
    assert slopes(t) <= math.tan(math.radians(47.0)) * (1 + 1e-3) + 2e-4


# ------------------------------------------------------------------------------------------------
# the wake: the hybrid law's undisturbed-grain rule
# ------------------------------------------------------------------------------------------------
def test_wake_only_with_the_hybrid_law_and_a_memory():
    """The wake is kept only when a region uses the hybrid law on a ground memory (every other scene has an empty one
    and runs none of it); it comes and goes with the regions."""
    m = mujoco.MjModel.from_xml_string(FOOT.format(hx=0.02, hy=0.02, hz=0.005))
    opts = GroundOptions(cell=CELL, extent=EXTENT, repose_angle=35.0)
    sizes = {(law, mem): GranularTerrain(m, "generic", law, resolution=0.005,
                                         ground_memory=opts if mem else False).terrain_state.g_wake.shape
             for law in ("rft", "hybrid") for mem in (False, True)}
    assert sizes[("hybrid", True)] == (32, 48, ground.WAKE_SLABS)
    assert all(s == (0, 0, 0) for k, s in sizes.items() if k != ("hybrid", True)), sizes
    t = GranularTerrain(m, "generic", "rft", resolution=0.005, ground_memory=opts)
    t.set_regions([mjrft.Region(-1.0, "generic", "hybrid")])
    assert t.terrain_state.g_wake.shape == (32, 48, ground.WAKE_SLABS) and np.all(np.isinf(t.terrain_state.g_wake))
    t.terrain_state.g_wake[3, 4, 5] = 0.25
    t.terrain_state.g_since[1] = 0.5
    t.reset()  # the prepared bed: no wake, the clock at 0
    assert np.all(np.isinf(t.terrain_state.g_wake)) and t.terrain_state.g_since[1] == 0.0
    t.set_regions(None)
    assert t.terrain_state.g_wake.size == 0


def test_wake_marks_the_slabs_a_leading_face_passed_and_ages_them():
    """A leading face 2 cm deep in a cell marks that cell's slabs around 2 cm; an element moving into them counts as in
    the wake only once it could not have made them itself (2 cell / speed + one update later). Controls: the same
    element 1 cm shallower (slabs not passed), too soon, moving away from the cell, and a cleared cell."""
    cell = 0.01
    frame = np.array([0.0, 0.0, cell, 1.0 / cell])
    base = np.zeros((3, 3))
    wake = np.full((3, 3, ground.WAKE_SLABS), np.inf, dtype=np.float32)
    ground._wake_mark(wake, 1, 1, 0.0, -0.02, 0.005, cell, 0.5)  # cell (j, i) = (1, 1): x, y in [0.01, 0.02)
    marked = np.flatnonzero(np.isfinite(wake[1, 1]))
    assert len(marked) == 2 and np.all(wake[1, 1, marked] == 0.5)  # 1.75-2.25 cm: the slabs 1.5-2 and 2-2.5 cm
    assert np.isfinite(wake).sum() == 2  # no other cell
    speed, period = 0.02, 0.004  # lag 2 x 0.01 / 0.02 + 0.004 = 1.004 s
    at = (0.008, 0.015, -0.02)  # in cell (1, 0), half a cell short of (1, 1), moving +x into it
    assert ground.in_wake(*at, 1.0, 0.0, 0.0, speed, frame, base, wake, 2.0, period)
    assert not ground.in_wake(0.008, 0.015, -0.01, 1.0, 0.0, 0.0, speed, frame, base, wake, 2.0, period)
    assert not ground.in_wake(*at, 1.0, 0.0, 0.0, speed, frame, base, wake, 1.4, period)
    assert not ground.in_wake(*at, -1.0, 0.0, 0.0, speed, frame, base, wake, 2.0, period)
    ground._wake_mark(wake, 1, 1, 0.0, -0.02, 0.005, cell, 1.9)  # a later pass keeps the earliest time
    assert ground.in_wake(*at, 1.0, 0.0, 0.0, speed, frame, base, wake, 2.0, period)
    wake[1, 1, :] = np.inf  # the body left the cell: the grains closed over the wake
    assert not ground.in_wake(*at, 1.0, 0.0, 0.0, speed, frame, base, wake, 2.0, period)
