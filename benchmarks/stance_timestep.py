"""The HUBO one-foot stance against the physics step and the granular coupling; writes
benchmarks/results/stance_timestep.txt.

The trials of the validation case ``thesis_hubo_stance`` on the 30.4 cm board (gait ``stance``, CoM 1 cm behind, over
and 1 cm ahead of the sole's centre, held to 10 s; :func:`mjrft.tools.validation.cases.thesis_hubo.run_trial`) at
the explicit granular step of 0.25, 0.5 and 1 ms and the implicit one at 1 and 2 ms (the 10 ms control period kept):
which trials stand, and when the others fall. It decides the humanoid env's default coupling (docs/numerics.md,
"Each env's physics step"). About 2 minutes on 2 cores.

    python benchmarks/stance_timestep.py
"""

from __future__ import annotations

import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
STEPS = ((0.00025, False), (0.0005, False), (0.001, False), (0.001, True), (0.002, True))


def main() -> None:
    from mjrft.tools.validation.cases import thesis_hubo as case

    t0 = time.perf_counter()
    lines = ["$ python benchmarks/stance_timestep.py",
             f"HumanoidSand-v0 one-foot stance on the 30.4 cm board, poppy_cp, held to {case.HOLD_END:g} s; CoM ahead of "
             "the sole's centre: " + ", ".join(f"{100 * c:+.0f} cm" for c in case.PLACEMENTS)]
    print("\n".join(lines), flush=True)
    for dt, implicit in STEPS:
        kw = dict(timestep=dt, frame_skip=round(0.01 / dt), implicit=implicit)
        falls = [case.run_trial(f"stance:com_x={cx},lift=0.1", 0.304, False, case.HOLD_END, env_kwargs=kw)[3]
                 for cx in case.PLACEMENTS]
        line = (f"  {'implicit' if implicit else 'explicit'} {dt * 1e3:4.2f} ms x {round(0.01 / dt):2d}: "
                + ", ".join("stood" if math.isnan(f) else f"fell at {f:.2f} s" for f in falls))
        print(line, flush=True)
        lines.append(line)
    lines.append(f"took {time.perf_counter() - t0:.0f} s")
    with open(os.path.join(HERE, "results", "stance_timestep.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())
