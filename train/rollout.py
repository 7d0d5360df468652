"""``mjrft rollout``: any policy or gait on any environment, headless, logged to a rerun file.

>>> from mjrft.train.rollout import rollout
>>> s = rollout("mjrft/HexapodSand-v0", "tripod:f=2", seconds=3, rrd_path="hex.rrd", env_kwargs={"medium": "poppy_lp"})
>>> s["distance"], s["mean_speed"], s["mean_sinkage_mm"]

Command line::

    mjrft rollout --env mjrft/HexapodSand-v0 --policy tripod:f=2 --seconds 5 --rrd hex.rrd medium=poppy_lp
    mjrft rollout --env mjrft/BipedSand-v0 --policy runs/biped/model.zip --seconds 10 --rrd biped.rrd --spawn-viewer

A policy is a gait spec (:mod:`mjrft.tools.gaits`, e.g. ``tripod:f=2.0``), a stable-baselines3 ``.zip`` saved
by ``mjrft train`` or by ``PPO.save`` / ``SAC.save`` (the algorithm is read from the run's
``config.json`` or from the zip; saved observation-normalisation statistics are applied), a run
folder, or any object with SB3's ``predict``. Env keyword arguments are ``key=value`` (JSON values,
else text: ``medium=poppy_lp resolution=0.01 pitch_free=false``).

The rollout starts from ``env.reset(seed=seed)``, acts deterministically, and runs ``seconds`` of
simulated time (rounded up to whole env steps; the registration's 10 s time limit is lifted to fit)
or until the episode terminates (the robot fell: ``fell`` in the summary). Frame 0 (after the reset)
and every ``log_every``-th env step are logged (:mod:`mjrft.tools.rerun_log`).

Summary (a dict; ``format_summary`` prints it):

=====================  ====================================================================================
``steps``, ``seconds``  env steps run and the simulated time they cover (s)
``distance``           torso displacement along +x (m), ``info["x_position"]`` at the end minus at reset
``mean_speed``         ``distance / seconds`` (m/s)
``mean_sinkage_mm``    mean over steps and feet/legs of ``info["sinkage"]``, counting a foot only while it
                       is in the sand (sinkage > 0); 0 if no foot ever entered it (rigid ground)
``peak_sinkage_mm``    largest ``info["sinkage"]`` over the rollout (mm)
``return``             sum of the env's rewards
``fell``               the episode terminated (unhealthy) before the time ran out
``diverged``           the simulation diverged (``info["diverged"]``: the NonFiniteError message), else
                       ""; the distance and sinkage of such a run mean nothing and are not printed
``frames``             frames logged; ``rrd`` the file (None without one); ``wall_s`` wall-clock seconds
=====================  ====================================================================================
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from mjrft.errors import check_positive
from mjrft.tools.outputs import number
from mjrft.tools.rerun_log import LOG_EVERY

from .artefacts import TRUST_HELP
from .common import check_env_id, check_int, check_mujoco_env, make_env, parse_kwargs, progress_bar
from .evaluate import DIVERGED_EXIT, announce_model, load_policy, resolve_model, trained_env


def _make_env(env_id: str, env_kwargs: dict):
    check_env_id(env_id)
    kwargs = dict(env_kwargs or {})
    # the rollout's own length governs; lift the registration's time limit out of the way
    kwargs.setdefault("max_episode_steps", NO_LIMIT)
    env = make_env(env_id, kwargs)
    try:
        check_mujoco_env(env, env_id)
    except ValueError:
        env.close()
        raise
    return env


NO_LIMIT = 2 ** 62


def bind_policy(policy_or_spec, env, trust: bool = False):
    """A ``predict``-able policy for ``env``: gait spec, SB3 zip / run folder, or an object with ``predict``
    (``trust``: also load model files that need pickle, :func:`mjrft.train.evaluate.load_policy`)."""
    from mjrft.tools.gaits import is_gait_spec, make_gait

    if isinstance(policy_or_spec, str) and is_gait_spec(policy_or_spec):
        return make_gait(policy_or_spec, env)
    if hasattr(policy_or_spec, "predict") and not isinstance(policy_or_spec, (str, Path)):
        return policy_or_spec
    return load_policy(policy_or_spec, env=env, trust=trust).bind(env)


def rollout(env_id_or_env, policy_or_spec, seconds: float | None = None, rrd_path=None, *, steps: int | None = None,
            log_every: int = LOG_EVERY, seed: int = 0, env_kwargs: dict | None = None, spawn_viewer: bool = False,
            deterministic: bool = True, progress: bool = False, trust: bool = False,
            viewer_bind: str = "127.0.0.1") -> dict:
    """Run one rollout and return its summary (see the module docstring).

    ``env_id_or_env``: a gymnasium id (made with ``env_kwargs``) or an env (used as is, not closed).
    Give ``seconds`` (simulated) or ``steps`` (env steps). ``rrd_path`` None and ``spawn_viewer`` False
    runs without logging. ``progress``: a progress bar (tqdm, on stderr) over the env steps. ``trust``:
    also load model files that need pickle (:func:`mjrft.train.evaluate.load_policy`). ``viewer_bind``: the
    address a spawned viewer listens on (:func:`mjrft.tools.rerun_log.spawn_viewer`; this machine only by
    default).
    """
    if (seconds is None) == (steps is None):
        raise ValueError("give exactly one of seconds (simulated time) or steps (env steps)")
    if seconds is not None:
        check_positive("seconds", seconds)
    else:
        steps = check_int("steps", steps, 1)
    log_every = check_int("log_every", log_every, 1)
    seed = check_int("seed", seed, 0)
    if isinstance(policy_or_spec, str):  # fail on a bad spec / path before building anything
        from mjrft.tools.gaits import is_gait_spec, parse_gait_spec

        if is_gait_spec(policy_or_spec):
            parse_gait_spec(policy_or_spec)
        else:
            resolve_model(policy_or_spec)  # a missing or damaged model file
    own_env = isinstance(env_id_or_env, str)
    if own_env:
        env = _make_env(env_id_or_env, env_kwargs or {})
    else:
        if env_kwargs:
            raise ValueError("env_kwargs apply only when the env is given by id")
        env = env_id_or_env
        check_mujoco_env(env, type(env.unwrapped).__name__)
    logger = None
    try:
        u = env.unwrapped
        if steps is None:
            steps = max(1, math.ceil(seconds / u.dt - 1e-9))
        policy = bind_policy(policy_or_spec, env, trust)
        if rrd_path is not None or spawn_viewer:
            from mjrft.tools.rerun_log import episode_logger

            source = policy_or_spec if isinstance(policy_or_spec, (str, Path)) else type(policy_or_spec).__name__
            logger = episode_logger(rrd_path, env, spawn=spawn_viewer, name=f"mjrft-rollout-{Path(str(source)).name}",
                                    viewer_bind=viewer_bind)
        t0 = time.perf_counter()
        obs, info = env.reset(seed=seed)
        x0 = float(info.get("x_position", u.data.qpos[0]))
        x = x0
        if logger is not None:
            logger.log(env)
        total = 0.0
        sink_sum, sink_n, sink_peak = 0.0, 0, 0.0
        terminated = truncated = False
        diverged = ""
        n = 0
        bar = progress_bar(steps, "rollout", progress)
        while n < steps and not (terminated or truncated):
            action, _ = policy.predict(obs, deterministic=deterministic)
            obs, reward, terminated, truncated, info = env.step(action)
            n += 1
            bar.update(1)
            total += float(reward)
            diverged = str(info.get("diverged") or "")
            x = float(info.get("x_position", u.data.qpos[0]))
            sink = np.asarray(info.get("sinkage", ()), dtype=np.float64)
            buried = sink[sink > 0]
            sink_sum += float(buried.sum())
            sink_n += len(buried)
            if len(sink):
                sink_peak = max(sink_peak, float(sink.max()))
            if logger is not None and n % log_every == 0:
                logger.log(env)
        bar.close()
        wall = time.perf_counter() - t0
        frames = logger.frames if logger is not None else 0
    finally:
        if logger is not None:
            logger.close()
        if own_env:
            env.close()
    seconds_run = n * u.dt
    distance = x - x0
    return {
        "env": env_id_or_env if own_env else type(u).__name__,
        "policy": str(policy_or_spec) if isinstance(policy_or_spec, (str, Path)) else type(policy_or_spec).__name__,
        "steps": n,
        "seconds": seconds_run,
        "distance": distance,
        "mean_speed": distance / seconds_run if seconds_run > 0 else 0.0,
        "mean_sinkage_mm": 1e3 * sink_sum / sink_n if sink_n else 0.0,
        "peak_sinkage_mm": 1e3 * sink_peak,
        "return": total,
        "fell": bool(terminated) and not diverged,
        "diverged": diverged,  # the NonFiniteError message when the simulation diverged (then no metrics hold)
        "frames": frames,
        "rrd": None if rrd_path is None else str(rrd_path),
        "wall_s": wall,
    }


def format_summary(s: dict) -> str:
    """A few aligned lines for the terminal (for a diverged run: what happened, no numbers)."""
    if s.get("diverged"):
        return (f"{s['policy']} on {s['env']}: DIVERGED after {s['steps']} steps ({s['seconds']:.2f} s simulated); "
                f"no distance, speed or sinkage is reported.\n  {s['diverged']}")
    lines = [
        f"{s['policy']} on {s['env']}: {s['seconds']:.2f} s simulated ({s['steps']} steps, {s['wall_s']:.1f} s wall)"
        + ("  -- FELL (episode terminated)" if s["fell"] else ""),
        f"  distance       {number(100 * s['distance'], '8.2f')} cm",
        f"  mean speed     {number(100 * s['mean_speed'], '8.2f')} cm/s",
        f"  mean sinkage   {number(s['mean_sinkage_mm'], '8.2f')} mm   (peak {number(s['peak_sinkage_mm'], '.2f')} mm)",
        f"  return         {number(s['return'], '8.2f')}",
    ]
    return "\n".join(lines)


def open_hint(path) -> str:
    return f"open it with:  rerun {path}     (or: python -m rerun {path})"


# ---------------------------------------------------------------------------------------------- CLI
def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--env", default=None, metavar="ID",
                        help="environment id, e.g. mjrft/HexapodSand-v0 (default: the one a model was trained on, "
                             "with its env kwargs; required for a gait)")
    parser.add_argument("--policy", required=True, metavar="PATH|GAIT",
                        help="SB3 model .zip / run folder, pretrained:HexapodSand-v0, or a gait spec such as "
                             "tripod:f=2.0 (gaits: tripod, rect, stand, shift)")
    parser.add_argument("--seconds", type=float, default=5.0, help="simulated seconds to run (default 5)")
    parser.add_argument("--rrd", default="rollout.rrd", metavar="FILE", help="rerun file to write (default rollout.rrd)")
    parser.add_argument("--log-every", type=int, default=LOG_EVERY, metavar="N",
                        help=f"log every N-th env step (default {LOG_EVERY})")
    parser.add_argument("--seed", type=int, default=0, help="reset seed (default 0)")
    parser.add_argument("--spawn-viewer", action="store_true", help="also stream to a newly started rerun viewer")
    parser.add_argument("--viewer-bind", default="127.0.0.1", metavar="ADDRESS",
                        help="with --spawn-viewer: the address the viewer listens on (default 127.0.0.1, this "
                             "machine only; 0.0.0.0 opens it to the network)")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    parser.add_argument("--trust", action="store_true", help=TRUST_HELP)
    parser.add_argument("env_kwargs", nargs="*", metavar="KEY=VALUE", help="environment keyword arguments")


def main(args) -> int:
    from mjrft.tools.outputs import WarningNotes, output_file

    output_file(args.rrd, "--rrd")
    if args.spawn_viewer:
        from mjrft.tools.rerun_log import check_viewer_display

        check_viewer_display()
    env_id, env_kwargs = args.env, parse_kwargs(args.env_kwargs)
    with WarningNotes() as notes:  # the warnings become notes under the summary, as for mjrft demo
        announce_model(args.policy)
        if env_id is None:
            env_id, saved_kwargs = trained_env(args.policy)
            env_kwargs = {**saved_kwargs, **env_kwargs}
        summary = rollout(env_id, args.policy, seconds=args.seconds, rrd_path=args.rrd, log_every=args.log_every,
                          seed=args.seed, env_kwargs=env_kwargs, spawn_viewer=args.spawn_viewer,
                          progress=args.progress, trust=args.trust, viewer_bind=args.viewer_bind)
    print(format_summary(summary))
    notes.print("  ")
    print(f"wrote {summary['rrd']} ({summary['frames']} frames, every {args.log_every} env steps)")
    print(open_hint(summary["rrd"]))
    return DIVERGED_EXIT if summary["diverged"] else 0
