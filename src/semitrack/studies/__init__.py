"""Layer 8: studies over many cases (random tracks, sweeps): one runner for one core, all cores or a dask cluster."""
