"""The design library over HTTP (/v1/library): the router, the worker side of a save, and the diff."""
