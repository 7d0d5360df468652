"""``mjrft train-mjx``: Brax PPO on an MJX environment of the registry under a named recipe or a recipe file, one
run (:func:`mjrft.train.mjx_ppo.train_recipe`) or one run per seed with the mean and spread over the seeds
(``--seeds``, :func:`mjrft.train.seeds.train_seeds`), each final policy evaluated on the MJX env and, with
``--cpu-episodes``, on the CPU env of the same task.

    mjrft train-mjx --config hexapod-sand --out runs/hexapod-sand-mjx
    mjrft train-mjx --config biped-sand --out runs/biped-sand-mjx --seeds 0 1 2
    mjrft train-mjx --config go2-joystick-sand --out runs/go2 --coordinator HOST:PORT --num-processes 2 --process-id 0
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from .mjx_ppo import (POLICY_FILE, check_devices, check_recipe, load_recipe, named_recipes, start_distributed,
                      train_recipe)
from .seeds import SEEDS_FILE, SEEDS_TABLE, check_seeds, evaluate_run, evaluation_lines, train_seeds


def add_arguments(parser) -> None:
    parser.add_argument("--config", default="hexapod-sand",
                        help=f"named MJX recipe ({', '.join(named_recipes()) or 'none'}) or a .yaml / .json file")
    parser.add_argument("--out", default="runs/hexapod-sand-mjx", help="run folder (policy.npz, policy.json, "
                                                                         "progress.csv, checkpoints/)")
    parser.add_argument("--timesteps", type=float, default=None, help="override num_timesteps (e.g. 2e7)")
    parser.add_argument("--num-envs", type=int, default=None, help="override num_envs (worlds per batch)")
    seeds = parser.add_mutually_exclusive_group()
    seeds.add_argument("--seed", type=int, default=None, help="override seed")
    seeds.add_argument("--seeds", type=int, nargs="+", default=None, metavar="SEED",
                       help="train one run per seed, each in OUT/seed-<SEED>/ (a seed whose folder holds a complete "
                            "run of the same recipe is not trained again), evaluate each, and write the mean and "
                            f"spread over the seeds to OUT/{SEEDS_TABLE} and OUT/{SEEDS_FILE}")
    parser.add_argument("--eval-episodes", type=int, default=8,
                        help="episodes of each final policy on the MJX env (0: none)")
    parser.add_argument("--cpu-episodes", type=int, default=None,
                        help="episodes of each final policy on the CPU env of the same task, the cross-check of the "
                             "two backends (mjrft eval; default 10 with --seeds, 0 for one run)")
    hosts = parser.add_argument_group("several hosts (jax.distributed; every local device is used in any case)")
    hosts.add_argument("--coordinator", default=None, metavar="HOST:PORT",
                       help="address of the first host's coordinator: start the same command on every host with "
                            "--num-processes and its own --process-id; the first host (id 0) writes the run folder")
    hosts.add_argument("--num-processes", type=int, default=None, help="number of hosts (processes) in the run")
    hosts.add_argument("--process-id", type=int, default=None, help="this host's index, 0 to num-processes - 1")


def _recipe_name(config) -> str:
    """The recipe's name as the command line gave it (a file's stem)."""
    path = Path(str(config))
    return path.stem if path.suffix.lower() in (".yaml", ".yml", ".json") else str(config)


def main(args) -> int:
    # leave device memory outside XLA's pool for kernel launches (docs/gpu.md); a user's own setting wins
    os.environ.setdefault("XLA_PYTHON_CLIENT_MEM_FRACTION", "0.6")
    cfg = load_recipe(args.config)
    if args.timesteps is not None:
        if not (math.isfinite(args.timesteps) and args.timesteps >= 1 and float(args.timesteps).is_integer()):
            raise ValueError(f"--timesteps must be a whole number >= 1, got {args.timesteps!r}")
        cfg["num_timesteps"] = int(args.timesteps)
    if args.num_envs is not None:
        cfg["num_envs"] = args.num_envs
    if args.seed is not None:
        cfg["seed"] = args.seed
    seeds = getattr(args, "seeds", None)
    if seeds is not None:
        check_seeds(seeds)
    for flag, value in (("--eval-episodes", args.eval_episodes), ("--cpu-episodes", args.cpu_episodes)):
        if value is not None and value < 0:
            raise ValueError(f"{flag} must be >= 0, got {value}")
    cpu_episodes = args.cpu_episodes if args.cpu_episodes is not None else (10 if seeds is not None else 0)
    cfg = check_recipe(cfg, f"MJX training recipe {args.config!r} with the command-line overrides")
    start_distributed(args.coordinator, args.num_processes, args.process_id)
    import jax

    check_devices(cfg)
    if seeds is not None:
        command = " ".join([f"mjrft train-mjx --config {args.config}"]
                           + [f"{flag} {value:g}" if isinstance(value, float) else f"{flag} {value}"
                              for flag, value in (("--timesteps", args.timesteps), ("--num-envs", args.num_envs))
                              if value is not None])
        train_seeds(cfg, args.out, seeds, eval_episodes=args.eval_episodes, cpu_episodes=cpu_episodes,
                    name=_recipe_name(args.config), command=command)
        return 0
    print(f"Brax PPO on {cfg['env']} ({cfg['num_envs']} worlds, {cfg['num_timesteps']:,} steps) on "
          f"{jax.device_count()} device(s) ({jax.devices()[0].platform}, {jax.process_count()} host(s)); "
          f"run folder {args.out}")
    summary = train_recipe(cfg, args.out)
    if jax.process_index() != 0:
        return 0
    print(f"trained in {summary['wall_s']:.1f} s; policy {Path(args.out) / POLICY_FILE}")
    if summary["env_id"] is None:  # an environment of MJX only (a Playground task): Brax's own evaluation
        ret = summary["final"].get("eval/episode_reward")
        print((f"final evaluation: return {ret:.3f}; " if ret is not None else "")
              + f"{cfg['env']} has no gymnasium env on the CPU (mjrft eval runs mjrft's robots' policies)")
        return 0
    row = evaluate_run(args.out, args.eval_episodes, cpu_episodes)
    for line in evaluation_lines(row):
        print(line)
    if not cpu_episodes:
        print(f"evaluate on the CPU env: mjrft eval --policy {args.out} --episodes 10")
    return 0


