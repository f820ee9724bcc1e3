"""One router per resource; every module here exposing ``router`` is mounted under /v1 by ``api.app``."""
