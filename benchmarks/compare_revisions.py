"""Run one benchmark script on an older revision and on the working tree, alternately, in one run.

    python benchmarks/compare_revisions.py REV [--rounds N] -- benchmarks/bench_envs.py --steps 300

The older revision is checked out into a temporary git worktree and imported through a temporary
folder that lays its files out as the installed package (``mjrft``, ``mjrft.envs``, ``mjrft.train``,
``mjrft.models``), put first on ``PYTHONPATH``; the working tree runs through the installed
(editable) package. Each revision runs its own copy of the benchmark script. The runs alternate
(old, new, old, new, ...) so that the machine's load falls on both alike; each run's output is
printed under its label. Ratios inside each benchmark (e.g. sand / rigid) are what to compare.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SUBPACKAGES = {"envs": "envs", "train": "train", "models": "models"}  # mjrft.<name> -> folder (pyproject)


def package_view(tree: str, into: str) -> str:
    """A folder holding ``mjrft/`` laid out like the installed package, made of links into ``tree``."""
    pkg = os.path.join(into, "mjrft")
    os.makedirs(pkg)
    for name in os.listdir(os.path.join(tree, "mjrft")):
        os.symlink(os.path.join(tree, "mjrft", name), os.path.join(pkg, name))
    for name, folder in SUBPACKAGES.items():
        if not os.path.exists(os.path.join(pkg, name)):
            os.symlink(os.path.join(tree, folder), os.path.join(pkg, name))
    return into


def run(label: str, cwd: str, script: list[str], pythonpath: str | None) -> None:
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath + os.pathsep + env.get("PYTHONPATH", "")
    print(f"===== {label} =====", flush=True)
    out = subprocess.run([sys.executable, *script], cwd=cwd, env=env, capture_output=True, text=True)
    print(out.stdout.rstrip(), flush=True)
    if out.returncode:
        print(out.stderr.rstrip()[-2000:], flush=True)
        raise SystemExit(f"{label}: the benchmark failed (status {out.returncode})")


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if "--" not in argv:
        raise SystemExit("usage: compare_revisions.py REV [--rounds N] -- SCRIPT [ARGS ...]")
    split = argv.index("--")
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("rev", help="the older revision (commit, tag or branch)")
    ap.add_argument("--rounds", type=int, default=2, help="old/new pairs (default 2)")
    args = ap.parse_args(argv[:split])
    script = argv[split + 1:]
    if not script:
        raise SystemExit("give the benchmark script after --")
    if args.rounds < 1:
        raise SystemExit(f"--rounds must be >= 1, got {args.rounds}")
    rev = subprocess.run(["git", "rev-parse", "--short", args.rev], cwd=REPO, capture_output=True, text=True)
    if rev.returncode:
        raise SystemExit(f"unknown revision {args.rev!r}: {rev.stderr.strip()}")
    short = rev.stdout.strip()
    with tempfile.TemporaryDirectory(prefix="mjrft-rev-") as tmp:
        tree = os.path.join(tmp, "tree")
        subprocess.run(["git", "worktree", "add", "--detach", "-q", tree, short], cwd=REPO, check=True)
        try:
            view = package_view(tree, os.path.join(tmp, "view"))
            for k in range(args.rounds):
                run(f"{short} (round {k + 1})", tree, script, view)
                run(f"working tree (round {k + 1})", REPO, script, None)
        finally:
            subprocess.run(["git", "worktree", "remove", "--force", tree], cwd=REPO, check=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
