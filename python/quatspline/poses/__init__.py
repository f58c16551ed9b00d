"""Pose trajectories: a rotation spline of any registered method plus a translation spline."""
