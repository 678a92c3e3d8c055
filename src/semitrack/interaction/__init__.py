"""Layer 7: a vehicle's run on the rail: one result, one input check and sampling, the routes beside them."""
