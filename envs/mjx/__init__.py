"""MJX environments in MuJoCo Playground's form (installed as ``mjrft.envs.mjx``); the registry is
:mod:`mjrft.mjx.envs`. Needs the optional extra ``mjrft[mjx]``."""
