"""Layer 1: the time and frequency-domain machinery of second-order systems, knowing nothing of tracks."""
