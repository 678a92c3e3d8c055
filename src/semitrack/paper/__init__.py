"""Layer 5: the paper's tables and statements, and the audits of them against our methods."""
