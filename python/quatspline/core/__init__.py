"""Rotation algebra on arrays: quaternions, conversions, two-key interpolation, dual
quaternions, metrics, means and integration."""
