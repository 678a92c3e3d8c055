"""Layer 0: what every other layer shares: input checks, conventions, the paper's numbers, old names."""
