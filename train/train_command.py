"""``mjrft train``: the command line of stable-baselines3 training, one run (:func:`mjrft.train.train.train`,
resumable) or one run per seed with the mean and spread over the seeds (``--seeds``,
:func:`mjrft.train.seeds.train_sb3_seeds`).

    mjrft train --env mjrft/HexapodSand-v0 --algo ppo --timesteps 200000 --out runs/hex resolution=0.02
    mjrft train --config hexapod-sand --out runs/hexapod-sand
    mjrft train --config hexapod-sand --out runs/hexapod-sand-seeds --seeds 0 1 2
"""

from __future__ import annotations

import argparse
from pathlib import Path

from mjrft.tools.outputs import output_dir

from .common import check_int, int_arg, parse_kwargs
from .config import DEFAULTS, load_training_config, named_configs
from .seeds import check_seeds, train_sb3_seeds
from .train import CHECKPOINT_DIR, load_config, train_settings
from .vecenv import KINDS


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--config", default=None, metavar="NAME_OR_FILE",
                        help="training configuration: a named recipe shipped with mjrft "
                             f"({', '.join(named_configs())}), a .yaml/.json file, or a run's config.json; "
                             "the options below override its values")
    parser.add_argument("--env", dest="env_id", default=None,
                        help="environment id, e.g. mjrft/HexapodSand-v0: a MuJoCo env with continuous actions "
                             "(required for a new run without --config)")
    parser.add_argument("--algo", default=None, help="ppo or sac (default ppo; on resume the saved one)")
    parser.add_argument("--timesteps", type=int_arg, default=None,
                        help="total environment steps of the run (resuming continues up to this; default 1e5, on "
                             "resume the saved budget)")
    parser.add_argument("--n-envs", type=int_arg, default=None,
                        help="parallel environments (default 1; on resume the saved number, a different one is "
                             "recorded as a change)")
    seeds = parser.add_mutually_exclusive_group()
    seeds.add_argument("--seed", type=int_arg, default=None,
                       help="random seed (default 0; on resume the saved one, a different one is refused)")
    seeds.add_argument("--seeds", type=int_arg, nargs="+", default=None, metavar="SEED",
                       help="train one run per seed, each in OUT/seed-<SEED>/ (the run of --seed SEED --out "
                            "OUT/seed-<SEED>: an interrupted one resumes, a complete one is not trained again), "
                            "evaluate each final policy (mjrft eval), and write the mean and spread over the seeds "
                            "to OUT/seeds.txt and OUT/seeds.json")
    parser.add_argument("--eval-episodes", type=int_arg, default=None,
                        help="with --seeds: deterministic episodes of each final policy on its env (default 10; 0: "
                             "none)")
    parser.add_argument("--out", default="runs/mjrft", help="run folder (default runs/mjrft; with --seeds the folder "
                                                            "of the seeds' run folders)")
    parser.add_argument("--checkpoint-every", type=int_arg, default=None,
                        help="steps between checkpoints (default 10000; on resume the saved one, a different one is "
                             "recorded as a change)")
    parser.add_argument("--hp", action="append", default=[], metavar="KEY=VALUE",
                        help="SB3 hyper-parameter, repeatable: --hp n_steps=512 --hp learning_rate=1e-4 "
                             "--hp 'policy_kwargs={\"net_arch\": [64, 64]}'")
    parser.add_argument("--normalize", action="store_true", default=None,
                        help="VecNormalize observations and rewards (statistics saved with the model)")
    parser.add_argument("--vec-env", default=None, choices=KINDS,
                        help="how the environments are stepped: subproc, dummy, batched or auto (default; "
                             "mjrft.train.vecenv; on resume the saved kind, another is recorded as a change)")
    parser.add_argument("--device", default=None,
                        help="torch device: cpu (default), cuda, auto (on resume the saved one, another is recorded "
                             "as a change)")
    parser.add_argument("--torch-threads", type=int_arg, default=None,
                        help="torch CPU threads (default 1: fastest for these small MLP policies; 0: torch's own "
                             "setting; on resume the saved number, another is recorded as a change)")
    parser.add_argument("--no-resume", dest="resume", action="store_false",
                        help="start over even if the folder has checkpoints")
    parser.add_argument("--trust", action="store_true",
                        help="on resume, also load checkpoint files that can only be unpickled (SB3's .pkl "
                             "side files): they can run code, so only for files from a trusted source")
    parser.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    parser.add_argument("--verbose", type=int, default=0, help="SB3 verbosity (1: training log)")
    parser.add_argument("env_kwargs", nargs="*", metavar="KEY=VALUE",
                        help="environment keyword arguments, e.g. resolution=0.02 medium=poppy_lp "
                             "max_episode_steps=500")


def run_settings(args) -> dict:
    """The run's settings from ``--config`` (if given) overridden by the options given on the command line.

    Without a file a setting not given is None: :func:`~mjrft.train.train.train` takes it from the run it resumes
    (else its default).
    """
    cfg = load_training_config(args.config) if args.config else {**{k: None for k in DEFAULTS}, "hyperparams": {},
                                                                   "env_kwargs": {}, "env_id": None}
    given = {"env_id": args.env_id, "algo": args.algo, "timesteps": args.timesteps, "n_envs": args.n_envs,
             "seed": args.seed, "checkpoint_every": args.checkpoint_every, "normalize": args.normalize,
             "vec_env": args.vec_env}
    cfg.update({k: v for k, v in given.items() if v is not None})
    cfg["hyperparams"] = {**cfg["hyperparams"], **parse_kwargs(args.hp, "--hp")}
    cfg["env_kwargs"] = {**cfg["env_kwargs"], **parse_kwargs(args.env_kwargs, "env kwarg")}
    return cfg


def recipe_command(args) -> str:
    """The ``mjrft train`` command line of ``args``'s settings without ``--seed(s)`` and ``--out``: what each seed of
    ``--seeds`` runs, which ``seeds.txt`` repeats."""
    import shlex

    parts = ["mjrft train"]
    for flag, value in (("--config", args.config), ("--env", args.env_id), ("--algo", args.algo),
                        ("--timesteps", args.timesteps), ("--n-envs", args.n_envs),
                        ("--checkpoint-every", args.checkpoint_every), ("--vec-env", args.vec_env),
                        ("--device", args.device), ("--torch-threads", args.torch_threads)):
        if value is not None:
            parts.append(f"{flag} {shlex.quote(str(value))}")
    parts += [f"--hp {shlex.quote(hp)}" for hp in args.hp]
    parts += [flag for flag, on in (("--normalize", args.normalize), ("--no-resume", not args.resume),
                                    ("--trust", args.trust)) if on]
    return " ".join(parts + [shlex.quote(kv) for kv in args.env_kwargs])


def main(args) -> int:
    cfg = run_settings(args)
    episodes = args.eval_episodes
    if args.seeds is None and episodes is not None:
        raise ValueError("--eval-episodes applies to --seeds (evaluate one run with mjrft eval --episodes N)")
    options = dict(resume=args.resume, device=args.device, torch_threads=args.torch_threads,
                   progress_bar=args.progress, verbose=args.verbose, config_name=args.config, trust=args.trust)
    if args.seeds is not None:
        check_seeds(args.seeds)
        episodes = 10 if episodes is None else check_int("--eval-episodes", episodes, 0)
        name = Path(args.config).stem if args.config else (cfg["env_id"] or "")
        train_sb3_seeds(cfg, output_dir(args.out), args.seeds, episodes=episodes, name=name,
                        command=recipe_command(args), report=print, **options)
        return 0
    out = Path(output_dir(args.out))
    result = train_settings(cfg, out, report=print, **options)
    cfg = load_config(result.config_path)
    if result.interrupted:
        saved = f"saved {result.model_path} and a checkpoint" if result.saved else "nothing new was saved"
        print(f"interrupted at {result.num_timesteps} steps; {saved}. Run the same command to resume.")
        return 130
    print(f"{cfg['algo'].upper()} on {cfg['env_id']}: {result.num_timesteps} steps; model {result.model_path}, "
          f"config {result.config_path}, {len(result.checkpoints)} checkpoint(s) in {out / CHECKPOINT_DIR}")
    print(f"evaluate: mjrft eval --policy {result.model_path} --episodes 10")
    return 0
