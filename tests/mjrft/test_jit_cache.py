"""Every process runs the same compiled code, whatever numba's cache holds and whichever function it calls first
(mjrft._jit_cache.load_cached_callees_first)."""

import json
import os
import subprocess
import sys

import pytest

from mjrft import _jit_cache, batch, kernel, stepping
from mjrft.implicit_step import implicit_wrench
from mjrft.laws.rft import rft_stress_batch

#: a child process: the sand hexapod under fixed random actions, optionally after a standalone kernel call
#: (which, without the callees-first loading, made the process run the kernel's own code instead of the copy
#: linked into the stepping loop); prints a hash of the final state
CHILD = """
import hashlib, json, sys, warnings
import gymnasium, numpy as np
import mjrft.envs
warnings.simplefilter("ignore")
env = gymnasium.make("mjrft/HexapodSand-v0")
env.reset(seed=0)
u = env.unwrapped
if sys.argv[1] == "compute-first":
    u.terrain.compute(u.data, 0.0)
rng = np.random.default_rng(0)
for _ in range(60):
    env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
h = hashlib.sha1(u.data.qpos.tobytes() + u.data.qvel.tobytes()).hexdigest()
from mjrft._jit_cache import loaded_count
print(json.dumps({"hash": h, "loaded": loaded_count()}))
"""


def _child(first: str) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, first], capture_output=True, text=True, timeout=600,
                         env={**os.environ, "PYTHONWARNINGS": "ignore"})
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_callees_come_before_their_callers():
    order = _jit_cache.callees_first([batch.run_batch_serial, batch.run_batch_parallel])
    at = {id(f): i for i, f in enumerate(order)}
    for callee, caller in ((kernel.terrain_kernel, stepping.run_steps), (kernel._scatter_batch, kernel.terrain_kernel),
                           (rft_stress_batch, kernel.terrain_kernel), (implicit_wrench, stepping.run_steps),
                           (stepping.run_steps, batch._step_one), (batch._step_one, batch.run_batch_parallel)):
        assert at[id(callee)] < at[id(caller)], (callee, caller)
    assert len(order) == len(at)  # each once


@pytest.mark.slow
def test_a_process_runs_the_same_code_whichever_kernel_it_calls_first():
    first = _child("step-first")  # fills the cache where it lacks these kernels (CI's first run)
    again = _child("step-first")
    other = _child("compute-first")
    assert again["loaded"] > 0  # the cache was used
    assert first["hash"] == again["hash"] == other["hash"]
