"""Layer 2: solution methods for the receptance of the periodic track, and its features."""
