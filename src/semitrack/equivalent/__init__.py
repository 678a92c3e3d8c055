"""Layer 3: equivalent multi-rigid-body systems: assembly, constraints, fitting, metrics, files."""
