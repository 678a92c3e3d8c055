"""Layer 3b: the broadband boundary: a passive rational model of the track's end stiffness."""
