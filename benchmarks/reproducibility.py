"""What a training run's bits depend on: the physics, the policy update and a short PPO run, each
fingerprinted under the CPU code paths another machine would take.

A run repeats itself bit for bit on one machine (same seed, ``n_envs``, vec env kind and torch
threads). Another CPU can still change the bits, because three libraries pick their code for the
CPU they run on: numba compiles mjrft's kernels for the host CPU (``NUMBA_CPU_NAME``), torch picks
its kernels by instruction set (``ATEN_CPU_CAPABILITY``) and MKL its BLAS paths
(``MKL_ENABLE_INSTRUCTIONS``; ``MKL_CBWR`` asks it for results that do not depend on them). Each
variant below runs in its own process with those variables set, as on a CPU of that kind, and
prints a hash of

* ``physics``: 300 steps of ``mjrft/HexapodSand-v0`` with fixed random actions (observations and
  final state), no torch involved;
* ``update``: 50 Adam steps of the recipe's MLP on fixed random data, no physics involved;
* ``ppo``: a short PPO run (2 x 256 env steps, the recipe's hyper-parameters otherwise) on the env.

Equal hashes mean equal bits; each variant is compared with the first one run (``host`` by
default), a ``portable+...`` variant with ``portable``. ``threads-2`` runs torch with 2 threads instead of the recipe's 1.
A ``...-fresh`` variant compiles mjrft's kernels in the run itself (an empty numba cache, as on the first run after
installing or changing mjrft) and is compared with its twin run from the cache (``host-fresh`` with ``host``,
``generic-fresh`` with ``numba-generic``; the script runs each twin once beforehand so that its cache is filled).

    python benchmarks/reproducibility.py                 # every variant
    python benchmarks/reproducibility.py --variants host numba-haswell
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile

VARIANTS = {
    "host": {},
    "threads-2": {"MJRFT_REPRO_THREADS": "2"},
    "numba-haswell": {"NUMBA_CPU_NAME": "haswell"},
    "numba-generic": {"NUMBA_CPU_NAME": "generic"},
    "torch-avx2": {"ATEN_CPU_CAPABILITY": "avx2"},
    "torch-default": {"ATEN_CPU_CAPABILITY": "default"},
    "mkl-avx2": {"MKL_ENABLE_INSTRUCTIONS": "AVX2"},
    "portable": {"NUMBA_CPU_NAME": "generic", "ATEN_CPU_CAPABILITY": "default", "MKL_CBWR": "COMPATIBLE"},
    "portable+mkl-avx2": {"NUMBA_CPU_NAME": "generic", "ATEN_CPU_CAPABILITY": "default", "MKL_CBWR": "COMPATIBLE",
                          "MKL_ENABLE_INSTRUCTIONS": "AVX2"},
    "host-fresh": {"MJRFT_CACHE_DIR": "(empty)"},
    "generic-fresh": {"NUMBA_CPU_NAME": "generic", "MJRFT_CACHE_DIR": "(empty)"},
}
#: the variant a ``...-fresh`` variant is compared with: the same settings, compiled code from the cache
CACHED_TWIN = {"host-fresh": "host", "generic-fresh": "numba-generic"}


def _digest(*arrays) -> str:
    import numpy as np

    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()[:16]


def physics_hash(steps: int = 300) -> str:
    import gymnasium
    import numpy as np

    import mjrft.envs  # noqa: F401  (registers the ids)

    env = gymnasium.make("mjrft/HexapodSand-v0")
    obs, _ = env.reset(seed=0)
    rng = np.random.default_rng(0)
    seen = [obs]
    for _ in range(steps):
        obs, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
        seen.append(obs)
    data = env.unwrapped.data
    out = _digest(np.array(seen), data.qpos, data.qvel)
    env.close()
    return out


def update_hash(steps: int = 50) -> str:
    import torch

    torch.manual_seed(0)
    net = torch.nn.Sequential(torch.nn.Linear(30, 64), torch.nn.Tanh(), torch.nn.Linear(64, 64), torch.nn.Tanh(),
                              torch.nn.Linear(64, 6))
    opt = torch.optim.Adam(net.parameters(), lr=3e-4)
    x, y = torch.randn(256, 30), torch.randn(256, 6)
    for _ in range(steps):
        opt.zero_grad()
        torch.nn.functional.mse_loss(net(x), y).backward()
        opt.step()
    return _digest(*[p.detach().numpy() for p in net.parameters()])


def ppo_hash() -> str:
    import gymnasium
    from stable_baselines3 import PPO

    import mjrft.envs  # noqa: F401

    env = gymnasium.make("mjrft/HexapodSand-v0")
    model = PPO("MlpPolicy", env, n_steps=256, batch_size=64, learning_rate=3e-4, gae_lambda=0.95, seed=0,
                policy_kwargs={"log_std_init": -0.5}, device="cpu")
    model.learn(512)
    env.close()
    return _digest(*[p.detach().numpy() for p in model.policy.parameters()])


def _child() -> None:
    import torch

    torch.set_num_threads(int(os.environ.get("MJRFT_REPRO_THREADS", "1")))
    print(json.dumps({"physics": physics_hash(), "update": update_hash(), "ppo": ppo_hash(),
                      "torch_cpu": torch.backends.cpu.get_cpu_capability()}))


def run_variant(extra: dict) -> dict:
    env = {**os.environ, **extra, "MJRFT_REPRO_CHILD": "1"}
    if "NUMBA_CPU_NAME" in extra:  # compiled for another CPU: keep the host's cache apart
        env["MJRFT_CACHE_DIR"] = os.path.join(os.path.expanduser("~"), ".cache", "mjrft-" + extra["NUMBA_CPU_NAME"])
    with tempfile.TemporaryDirectory() as empty:
        if extra.get("MJRFT_CACHE_DIR") == "(empty)":
            env["MJRFT_CACHE_DIR"] = empty
        out = subprocess.run([sys.executable, __file__], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=list(VARIANTS))
    args = ap.parse_args(argv)
    for twin in {CACHED_TWIN[n] for n in args.variants if n in CACHED_TWIN}:  # fill the twins' caches
        run_variant(VARIANTS[twin])
    rows = {name: run_variant(VARIANTS[name]) for name in args.variants}
    print(f"{'variant':<18} {'against':<9} {'physics':<8} {'update':<8} {'ppo':<8} {'torch':<8} settings")
    for name, r in rows.items():
        against = "portable" if name.startswith("portable+") and "portable" in rows else next(iter(rows))
        against = CACHED_TWIN[name] if CACHED_TWIN.get(name) in rows else against
        ref = rows[against]
        same = ["same" if r[k] == ref[k] else "DIFFERS" for k in ("physics", "update", "ppo")]
        settings = " ".join(f"{k}={v}" for k, v in VARIANTS[name].items()) or "(none)"
        print(f"{name:<18} {against:<9} {same[0]:<8} {same[1]:<8} {same[2]:<8} {r['torch_cpu']:<8} {settings}")
    print("hashes:", json.dumps({n: {k: r[k] for k in ("physics", "update", "ppo")} for n, r in rows.items()}))


if __name__ == "__main__":
    if os.environ.get("MJRFT_REPRO_CHILD"):
        _child()
    else:
        main()
