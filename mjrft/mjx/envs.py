"""The registry of mjrft's MJX environments, as MuJoCo Playground's ``registry``: names, configs, loading.

>>> mjrft.mjx.envs.names()
('Go2JoystickRigid', 'Go2JoystickSand')
>>> env = mjrft.mjx.envs.load("Go2JoystickSand", config_overrides={"sand.medium": "poppy_lp"})

Each environment module of :mod:`mjrft.envs.mjx` lists its entries in ``ENVS`` (name -> (make(config,
config_overrides), default config)); this module collects them, and :func:`register` adds one of a user's.
"""

from __future__ import annotations

from mjrft.errors import unknown


_REGISTERED: dict = {}  # register()'s entries


def _entries() -> dict:
    from mjrft.envs.mjx import go2_joystick

    return {**go2_joystick.ENVS, **_REGISTERED}


def register(name: str, make, default_config) -> None:
    """Add an environment: ``make(config, config_overrides)`` builds it, ``default_config()`` gives its configuration
    (Playground's ``register_environment``); ``mjrft train-mjx`` recipes can then name it."""
    if not isinstance(name, str) or not name:
        raise ValueError(f"an MJX environment's name must be a non-empty string, got {name!r}")
    _REGISTERED[name] = (make, default_config)


def names() -> tuple[str, ...]:
    """The registered environment names."""
    return tuple(_entries())


def _entry(name: str):
    entries = _entries()
    if name not in entries:
        raise unknown("MJX environment", name, entries)
    return entries[name]


def get_default_config(name: str):
    """A fresh copy of ``name``'s default configuration (an ``ml_collections.ConfigDict``)."""
    return _entry(name)[1]()


def load(name: str, config=None, config_overrides: dict | None = None):
    """The environment ``name`` with ``config`` (default :func:`get_default_config`) and ``config_overrides`` (a flat
    dict, ``{"sand.medium": "poppy_lp"}``)."""
    make, default = _entry(name)
    return make(default() if config is None else config, config_overrides)
