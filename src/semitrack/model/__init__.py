"""Layer 2: what a track and a vehicle are: parameters, the periodic cell, the beam, roughness, track files."""
