"""A vehicle's run on the rail (layer 7): one result, one input check and sampling, the routes beside them."""
