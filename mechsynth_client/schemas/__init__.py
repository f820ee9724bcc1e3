"""Request and response models of the HTTP API (pydantic v2); their examples make /docs the user manual."""

# flywheel before foundation: foundation takes the motor's schema from flywheel, which takes the elastic drive's
# schemas from foundation once its motor is defined.
from . import flywheel as _flywheel  # noqa: E402,F401
