"""mjrft's tools: what is built on the physics core (:mod:`mjrft.coupler` and the modules it is built from,
:mod:`mjrft.kernel`, :mod:`mjrft.batch`, :mod:`mjrft.media`, :mod:`mjrft.laws`, :mod:`mjrft.geometry`,
:mod:`mjrft.errors`) and the models (:mod:`mjrft.models`).
The core and the models import none of them; the environments (:mod:`mjrft.envs`) and training
(:mod:`mjrft.train`) are built on them (``tests/test_layout.py`` checks the layers).

===============  ============================================================================
module           what it is
===============  ============================================================================
``cli``          the ``mjrft`` command line: one subcommand per task, each in its own module
``settle``       ``mjrft settle``: a box foot and a legged body dropped on sand, sinkage vs analytic
``rigs``         the plate-intruder and rotating-leg measurement rigs (``mjrft rig``)
``gaits``        the papers' open-loop gaits, as policies with the stable-baselines3 interface
``presets``      the environments' speed/accuracy presets: fast, default, accurate
``tradeoff``     the speed/accuracy trade study (``mjrft bench``)
``calibration``  fits of the wet-sand speed factor and the hybrid law's bar-drag constants
``rerun_log``    logging a simulation with its terrain to a rerun file or viewer
``outputs``      output paths checked before any work starts; numbers printed without noise
``validation``   the source papers' experiments and the validation report (``mjrft validate``)
===============  ============================================================================

>>> from mjrft.tools import gaits, rigs
>>> import mjrft.tools.validation

This package imports none of them itself: each is imported when it is used.
"""

__all__ = ["calibration", "cli", "gaits", "outputs", "presets", "rerun_log", "rigs", "settle", "tradeoff",
           "validation"]
