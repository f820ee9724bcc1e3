"""Request and response models of the HTTP API (pydantic v2); their examples make /docs the user manual."""
