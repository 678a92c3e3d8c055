"""Layer 9: the paper's tables and statements, the audits of them against our methods, the chapters' studies."""
