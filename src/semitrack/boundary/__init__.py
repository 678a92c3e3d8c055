"""Layer 5: the broadband boundary: a passive rational model of the track's end stiffness."""
