"""Layer 1: what a track is: parameters, the periodic cell, the Timoshenko beam, track files."""
