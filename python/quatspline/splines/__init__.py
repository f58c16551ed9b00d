"""Rotation and pose splines, one module per family, with joint continuity and retiming."""
