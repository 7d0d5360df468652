"""How many of the hexapod's elements are below the surface at once: the bound ``Sand(cull=K)`` must stay above.

``mjrft/HexapodSand-v0`` (the default robot, C-legs, poppy_cp) walks the open-loop tripod at 1-5 Hz for 6 s each
(``max_hip_speed = 12 pi``, the 5 Hz tripod needs 10 pi); after every physics step the elements with depth > 0
are counted. Printed: the largest count per frequency and over all of them, against the element total.

    python benchmarks/buried_elements.py        # writes benchmarks/results/buried_elements.txt
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import gymnasium
import numpy as np

import mjrft.envs  # noqa: F401  (registers the environments)
from mjrft.tools.gaits import make_gait

OUT = Path(__file__).parent / "results" / "buried_elements.txt"


def most_buried(f: float, seconds: float = 6.0) -> tuple[int, int]:
    """The largest number of elements below the surface after any physics step, and the element total."""
    env = gymnasium.make("mjrft/HexapodSand-v0", max_hip_speed=12 * math.pi, terminate_when_unhealthy=False)
    u = env.unwrapped
    obs, _ = env.reset(seed=0)
    gait = make_gait(f"tripod:f={f:g}", env)
    terrain, most = u.terrain, [0]

    def count(data):  # after every physics step, so every step is counted
        most[0] = max(most[0], int(np.count_nonzero(terrain.depth > 0)))

    u.each_physics_step(count)
    for _ in range(int(round(seconds / u.dt))):
        action, _ = gait.predict(obs)
        obs, *_ = env.step(action)
    env.close()
    return most[0], terrain.n_elements


def main() -> None:
    warnings.simplefilter("ignore")
    lines = ["python benchmarks/buried_elements.py",
             "mjrft/HexapodSand-v0 (C-legs, poppy_cp), tripod for 6 s: most elements below the surface after any step"]
    worst = 0
    for f in (1.0, 2.0, 3.0, 4.0, 5.0):
        most, total = most_buried(f)
        worst = max(worst, most)
        lines.append(f"  {f:g} Hz: {most} of {total}")
    lines.append(f"at most {worst} of {total} elements buried")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    OUT.write_text(text)


if __name__ == "__main__":
    main()
