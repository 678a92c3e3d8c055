"""Layer 6: finite-element tracks (long and truncated), the infinite FE track, loads in time, truncation studies."""
