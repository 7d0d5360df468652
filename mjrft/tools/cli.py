"""The ``mjrft`` command line: one entry point, one subcommand per task (``mjrft <command> --help``).

Each subcommand lives in its own module, which provides ``add_arguments(parser)`` and
``main(args) -> int``; the module is imported only when its command runs, so ``mjrft --help`` and
the light commands stay fast and work without the optional extras.

========  =================================  =====================================================
command   module                             what it does
========  =================================  =====================================================
demo      ``mjrft.train.demo``               hexapod tripod gait on poppy seeds, logged to rerun
settle    ``mjrft.tools.settle``             drop a box foot and a legged body; sinkage vs analytic
rig       ``mjrft.tools.rigs``               plate-intruder and rotating-leg rigs; arrays + plots
train     ``mjrft.train.train_command``      stable-baselines3 training (PPO/SAC), resumable
train-mjx ``mjrft.train.train_mjx``          Brax PPO on an MJX env (thousands of worlds per GPU)
eval      ``mjrft.train.evaluate``           deterministic evaluation of a policy or gait
plot      ``mjrft.train.plot``               learning curves of training runs (return, speed)
rollout   ``mjrft.train.rollout``            any policy or gait, any env, headless, to a rerun file
bench     ``mjrft.tools.tradeoff``           the speed/accuracy trade study
sweep     ``mjrft.train.sweep``              parameter grids, local processes or Ray, resumable
validate  ``mjrft.tools.validation.report``  rerun the papers' experiments; Markdown report + plots
========  =================================  =====================================================
"""

from __future__ import annotations

import argparse
import importlib
import sys

COMMANDS = {
    "demo": ("mjrft.train.demo", "hexapod tripod gait on poppy seeds, headless, logged to a rerun file"),
    "settle": ("mjrft.tools.settle", "drop a box foot and a legged body onto sand; print sinkage vs analytic"),
    "rig": ("mjrft.tools.rigs", "run the plate-intruder or rotating-leg rig; save force profiles and plots"),
    "train": ("mjrft.train.train_command", "train a policy with stable-baselines3 (PPO or SAC), resumable"),
    "train-mjx": ("mjrft.train.train_mjx", "train an MJX env (mjrft.mjx.envs) with Brax's PPO (GPU; needs mjrft[mjx])"),
    "eval": ("mjrft.train.evaluate", "evaluate a trained policy or an open-loop gait; print a table"),
    "plot": ("mjrft.train.plot", "plot learning curves (episode return, forward speed) of training runs"),
    "rollout": ("mjrft.train.rollout", "roll out a policy or gait headless and log it to a rerun file"),
    "bench": ("mjrft.tools.tradeoff", "measure the speed/accuracy trade of resolution, law and timestep"),
    "sweep": ("mjrft.train.sweep", "run a parameter grid (local processes or Ray), resumable"),
    "validate": ("mjrft.tools.validation.report", "rerun the source papers' experiments and write a validation report"),
}


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser; only ``command``'s module is imported (all of them when ``command`` is None)."""
    parser = argparse.ArgumentParser(prog="mjrft", description="Granular terrain (RFT) for MuJoCo.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (module, help_text) in COMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        if command is None or name == command:
            importlib.import_module(module).add_arguments(p)
    return parser


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((a for a in argv if not a.startswith("-")), None)
    parser = build_parser(command if command in COMMANDS else "")
    args = parser.parse_args(argv)
    from mjrft.tools.outputs import remove_empty_created

    try:
        module = importlib.import_module(COMMANDS[args.command][0])
        return int(module.main(args) or 0)
    except (ValueError, KeyError) as exc:  # bad user input: one clear line, exit status 2
        remove_empty_created()  # an --out folder made for a run that never started
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        parser.exit(2, f"mjrft {args.command}: error: {msg}\n")
    except KeyboardInterrupt:  # Ctrl-C before a command saves anything of its own: no traceback
        remove_empty_created()
        sys.stderr.write(f"mjrft {args.command}: interrupted\n")
        return 130


if __name__ == "__main__":
    sys.exit(main())
