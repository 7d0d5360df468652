"""Warnings during training: each distinct warning shown once with a count, and every one logged to the run folder.

Under random actions the terrain may warn every few episodes (``TerrainStabilityWarning``, one per body
and time), from every worker process, each with its own source line. Training instead:

* wraps each training environment in :class:`CaptureWarnings`, which records the warnings raised during
  ``step``/``reset`` into ``info["warnings"]`` (category name and message) instead of printing them;
* runs :func:`warning_tally` as a callback in the trainer: the first warning of each kind is printed
  once (a kind is the category and the message with its numbers blanked, e.g. the same body's stability
  warning at any time), every warning is appended to ``warnings.csv`` in the run folder (step, env
  index, category, message; flushed per row), and the end of training prints one line per kind with
  its count.
"""

from __future__ import annotations

import csv
import warnings
from pathlib import Path

import gymnasium

from mjrft.tools.outputs import warning_kind

WARNINGS_CSV = "warnings.csv"


class CaptureWarnings(gymnasium.Wrapper):
    """Puts the warnings raised during ``step`` and ``reset`` into ``info["warnings"]`` (not printed)."""

    def step(self, action):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            obs, reward, terminated, truncated, info = self.env.step(action)
        if caught:
            info = {**info, "warnings": [(w.category.__name__, str(w.message)) for w in caught]}
        return obs, reward, terminated, truncated, info

    def reset(self, **kwargs):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            obs, info = self.env.reset(**kwargs)
        if caught:
            info = {**info, "warnings": [(w.category.__name__, str(w.message)) for w in caught]}
        return obs, info


def warning_tally(out_dir, echo=print):
    """The SB3 callback that shows each kind of warning once, logs all of them, and prints the counts."""
    from stable_baselines3.common.callbacks import BaseCallback

    path = Path(out_dir) / WARNINGS_CSV

    class WarningTally(BaseCallback):
        def _on_training_start(self) -> None:
            self.counts: dict[str, int] = {}
            new = not path.exists() or path.stat().st_size == 0
            self._file = open(path, "a", newline="")
            self._csv = csv.writer(self._file)
            if new:
                self._csv.writerow(("step", "env", "category", "message"))
                self._file.flush()

        def _on_step(self) -> bool:
            for i, info in enumerate(self.locals.get("infos") or ()):
                for category, message in info.get("warnings", ()):
                    kind = warning_kind(category, message)
                    if kind not in self.counts:
                        echo(f"{category} (shown once; all in {path}): {message}")
                    self.counts[kind] = self.counts.get(kind, 0) + 1
                    self._csv.writerow((self.num_timesteps, i, category, message))
                    self._file.flush()
            return True

        def _on_training_end(self) -> None:
            self._file.close()
            if self.counts:
                echo(f"{sum(self.counts.values())} warning(s) of {len(self.counts)} kind(s) during training "
                     f"(all in {path}):")
                for kind, n in sorted(self.counts.items(), key=lambda kv: -kv[1]):
                    echo(f"  {n:6d} x {kind}")

    return WarningTally()
