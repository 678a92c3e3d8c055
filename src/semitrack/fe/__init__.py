"""Layer 4: finite-element tracks (long and truncated), time integration, truncation studies."""
