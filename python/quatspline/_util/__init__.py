"""Internal utilities: array checks, atomic output, progress bars, threads, SIMD selection."""
