"""Scene files, ground motions, results, VTK and plots."""
