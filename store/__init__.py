"""The service's store, outside the engine: studies and their rows, users and API tokens, the design library.

One data layer (SQLAlchemy Core) over two engines: a SQLite file by default, PostgreSQL when
``SYNTH_DATABASE_URL`` points at one. Alembic migrations bring the schema up to date at start.
"""

from .db import MigrationFailed, Store, StoreUnavailable, database_url
from .studies import LeaseLost, SqlStudyStore, process_owner
from .users import ROLES, User, Users, token_hash

__all__ = [
    "ROLES",
    "LeaseLost",
    "MigrationFailed",
    "SqlStudyStore",
    "Store",
    "StoreUnavailable",
    "User",
    "Users",
    "database_url",
    "process_owner",
    "token_hash",
]
