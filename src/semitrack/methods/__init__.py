"""Layer 3: solution methods for the receptance of the periodic track, and its features."""
