"""Smoothing splines fitted to noisy samples, and minimum-energy interpolation."""
