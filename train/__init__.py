"""Training, evaluation and rollout scripts (stable-baselines3); installed as ``mjrft.train``."""
