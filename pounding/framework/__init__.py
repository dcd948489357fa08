"""Model, assembly, registries and the analysis driver."""
