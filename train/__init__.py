"""Training, evaluation and rollout scripts (stable-baselines3); installed as ``mjrft.train``."""

import sys as _sys

if getattr(_sys.modules.get("mjrft"), "__file__", None) is None:  # a clone folder named mjrft, found first
    raise ImportError(f"{__name__} was imported from a folder named 'mjrft' that holds the mjrft repository, not from "
                      "the installed package: run the script from another folder (or inside the repository)")
