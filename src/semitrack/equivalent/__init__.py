"""Layer 4: equivalent multi-rigid-body systems: assembly, constraints, fitting, metrics, files."""
