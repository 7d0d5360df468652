"""The speed/accuracy trade study (``mjrft bench``): element resolution, force law, timestep, frame skip.

For four standard scenarios the study runs a grid of configurations, each one side by side with the
bare MuJoCo model, and reports the cost per simulated second relative to the bare model and the
error against a converged reference::

    mjrft bench --quick --out bench_out            # small grid, half the simulated time, about a minute
    mjrft bench --scenarios hexapod,plate          # the full grid of two scenarios
    python benchmarks/trade_study.py               # full study -> benchmarks/results/

Outputs (in ``--out``): ``trade_study.md`` (Markdown table), ``trade_study.csv`` (one row per
scenario and configuration) and ``trade_study.png`` (Pareto plot: cost ratio against force error).

Scenarios (:data:`SCENARIOS`)
-----------------------------
``hexapod``   RHex-class hexapod (:func:`mjrft.models.hexapod_model`, C-legs, poppy_cp), open-loop
              alternating tripod at 2 Hz (hip position targets advancing at 4 pi rad/s, tripod B half
              a turn ahead, as ``benchmarks/bench_step.py``), 2 s. Granular bodies: torso + six legs.
``humanoid``  HUBO-class humanoid standing on its right foot, 2.5 s: a posture controller leans both
              legs (hip roll = -ankle roll, a parallelogram) to bring the centre of mass over the right
              sole (PD on the centre of mass, 0-1 s), then folds the left leg up (hip pitch -0.6, knee
              1.2, ankle pitch -0.6 rad, 1.2-1.8 s); the right ankle pitch holds the centre of mass over
              the sole fore-aft. The feet are Li/HUBO's widest boards, 30.4 cm wide (reference section 6):
              on the default 15.2 cm feet one-foot stance on poppy seeds topples in every configuration
              (the plastic rolling resistance of a plate, about ``alpha_z L w^3 / 12`` = 31 N m/rad, is
              far below the body's toppling stiffness ``m g h`` = 330 N m/rad; it grows as ``w^3``).
``plate``     Li 2013's plate (3.81 x 2.54 x 0.64 cm, :func:`mjrft.models.rigs.plate_rig_xml`) at attack
              angle beta = 30 deg, driven at 4 cm/s along intrusion angle gamma = 60 deg from 1 cm above
              the surface to 5.6 cm centre depth, 2 s.
``hexapod_small`` The DynaRoACH-sized hexapod (:func:`mjrft.models.hexapod_model` ``variant="small"``, 25 g,
              C-legs of 1 cm radius) on 3 mm glass (``glass3_cp``, the DynaRoACH paper's medium) with its
              scene's dry inertial regime on (:mod:`mjrft.laws.inertial`), open-loop alternating tripod at
              10 Hz (the paper's fluid-like running range), 1 s. Granular bodies: torso + six legs.
``cleg``      Li 2013's leg-rotation rig (:func:`mjrft.models.rigs.leg_rig_xml`, C-leg: one closed mesh, a
              semicircle of 7.62 cm chord, 2.54 cm wide, 0.64 cm thick, axle 2 cm above the surface) turning at
              pi/2 rad/s from leg angle -pi/2 to +pi/2, 2 s (Li's 0.2 rad/s would take 16 s; the dry
              laws are rate-independent, so only the wet law notices the speed).

The rigs are kinematic: their joints get an armature of 1e6 (kg or kg m^2), so the granular forces
cannot change their motion, and ``qpos``/``qvel`` are re-prescribed every control period.

Configurations (:func:`default_grid`)
-------------------------------------
One factor at a time around the scenario's default (the model's own resolution, ``rft`` with the
medium's own Li fit, 1 ms x 10 steps per control period):

* resolution: 4, 2, 1, 1/2 and 1/4 x the model's resolution (hexapod 5 mm, humanoid 2 cm); the rigs
  (5 mm) stop at 1/2, where they have converged (1/2 and 1/4 differed by < 0.05 % in a trial run);
* law: ``depth_only``; ``rft_generic`` (Li RFT with the generic profile scaled to the medium's zeta,
  i.e. Li's scaling routine instead of a measured fit); ``rft`` (the medium's own fit); ``rft3d``;
  ``wet`` (SGRFT speed factor on the medium's own fit; on the rigs: the plate's 40 mm/s lies inside
  its 10-50 mm/s calibration, the C-leg's elements move up to 12 cm/s, where the factor is held at its
  50 mm/s value) and ``hybrid`` (curved-leg model, with the leg's width and maximum depth as
  :mod:`mjrft.tools.rigs` gives them; C-leg rig only); ``rft_inertial`` (the medium's own fit plus the dry
  inertial regime, :mod:`mjrft.laws.inertial`; RHex-class hexapod: its legs pass poppy seeds' critical
  speed sqrt(2 g d) = 11.7 cm/s) and ``rft_quasistatic`` (the small hexapod's scene with the regime
  off). Rows of ``wet``, ``hybrid``, ``rft_inertial`` and ``rft_quasistatic`` measure a different
  physics, not a discretisation error;
* timestep: 2, 1, 0.5 ms at a fixed control period of 10 ms (frame skip 5, 10, 20);
* frame skip at 1 ms: 1, 5, 10, 20 (the control period changes with it);
* the presets of :mod:`mjrft.tools.presets` (``fast``, ``accurate``; ``default`` is the default row).

Reference (error zero by definition): the scenario's finest resolution (robots 1/4 x, rigs 1/2 x) with
the smallest timestep (0.5 ms x 20) and the medium's own Li fit.

Measurements
------------
* cost: wall time of one rollout with terrain over wall time of the same rollout of the bare model,
  i.e. cost per simulated second relative to plain MuJoCo. The bare model of a robot is its
  rigid-ground twin (``sand=False``: MuJoCo contacts instead of grains) running the same controller;
  that of a rig is the rig without terrain (a few microseconds per step, so a rig's ratio is
  essentially the terrain's own cost in units of a trivial MuJoCo step). Bare runs use the models'
  default 1 ms x 10. The terrain and bare rollouts alternate (bare, terrain, bare, ..., terrain, bare;
  up to ``repeats`` terrain samples, fewer once 2 s with terrain have been timed; a rollout shorter
  than 0.1 s is repeated back to back within its sample); each terrain sample is divided by the mean of
  the two bare samples around it and the median of these ratios is reported, so a noisy, shared machine
  affects both sides alike. Compilation and model set-up are outside the timing.
* errors, from a separate (untimed) recording run sampled every 2 ms of simulated time (the same
  instants in every configuration; stepping in pieces does not change the physics):

  - peak force: ``| max_t |F| - max_t |F_ref| | / max_t |F_ref|``, F the net granular force on the
    scenario's bodies (robot: all granular bodies; rig: the plate or leg);
  - RMS force: ``sqrt(mean_t |F - F_ref|^2) / sqrt(mean_t |F_ref|^2)``;
  - final position: distance (mm) between the final positions of the torso / pelvis (robots only;
    a rig's motion is prescribed);
  - sinkage: difference (mm) of the mean, over the last quarter of the run, of the deepest element
    depth of the granular bodies (robots only).

A configuration whose run raises :class:`~mjrft.errors.NonFiniteError` is reported as ``failed``;
stability warnings (:class:`~mjrft.errors.TerrainStabilityWarning`) are counted in ``warnings``.

Modules
-------
==============  =====================================================================================
``scenarios``   the scenarios (:data:`SCENARIOS`) and the grid of configurations (:func:`default_grid`)
``measure``     the runs: recordings, errors against the reference, the cost (:func:`run_study`)
``report``      the CSV and Markdown tables, the presets' choice and the Pareto plot (:func:`write_outputs`)
``command``     ``mjrft bench`` (:func:`add_arguments`, :func:`main`)
==============  =====================================================================================

Every public name of the four is importable from this package.
"""

from __future__ import annotations

from .scenarios import (BOARD_WIDTH, CONTROL_PERIOD, Config, DRY_LAWS, FRAME_SKIPS, INERTIAL_VARIANTS, LAW_VARIANTS,
                        LEG_OMEGA, LEG_START, MODEL_DIFFERENCE_LAWS, PLATE_BETA, PLATE_GAMMA, PLATE_SPEED, PLATE_START,
                        REFERENCE_LAW, RESOLUTION_SCALES, RIG_ARMATURE, RIG_RESOLUTION_SCALES, SCENARIOS, SMALL_FREQ,
                        SMALL_MEDIUM, Scenario, TIMESTEPS, dedupe, default_grid, get_scenario, reference_config)
from .measure import (MIN_SAMPLE, MIN_TIMED, QUICK_DURATION, Row, SAMPLE_DT, Trace, errors, law_and_medium,
                      make_terrain, record, run_scenario, run_study)
from .report import (ACCURATE_GAIN, CSV_FIELDS, ERROR_FLOOR, FACTOR_STYLE, markdown_table, pareto_front, plot_pareto,
                     recommend_presets, recommendation_text, write_csv, write_markdown, write_outputs)
from .command import add_arguments, main, parse_scenarios

__all__ = ["ACCURATE_GAIN", "BOARD_WIDTH", "CONTROL_PERIOD", "CSV_FIELDS", "Config", "DRY_LAWS", "ERROR_FLOOR",
           "FACTOR_STYLE", "FRAME_SKIPS", "INERTIAL_VARIANTS", "LAW_VARIANTS", "LEG_OMEGA", "LEG_START", "MIN_SAMPLE",
           "MIN_TIMED", "MODEL_DIFFERENCE_LAWS", "PLATE_BETA", "PLATE_GAMMA", "PLATE_SPEED", "PLATE_START",
           "QUICK_DURATION", "REFERENCE_LAW", "RESOLUTION_SCALES", "RIG_ARMATURE", "RIG_RESOLUTION_SCALES", "Row",
           "SAMPLE_DT", "SCENARIOS", "SMALL_FREQ", "SMALL_MEDIUM", "Scenario", "TIMESTEPS", "Trace", "add_arguments",
           "dedupe", "default_grid", "errors", "get_scenario", "law_and_medium", "main", "make_terrain",
           "markdown_table", "pareto_front", "parse_scenarios", "plot_pareto", "recommend_presets",
           "recommendation_text", "record", "reference_config", "run_scenario", "run_study", "write_csv",
           "write_markdown", "write_outputs"]
