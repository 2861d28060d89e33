"""Attitude filters (QNCF, RAMS EKF, baselines)."""
