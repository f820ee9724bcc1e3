"""The service's store (studies, designs, users): opened from the settings, migrated at start, reported by
``/ready``, and handed to the routers as a dependency."""

from __future__ import annotations

import logging
from typing import Annotated, Any

from fastapi import Depends, Request

from store import MigrationFailed, Store, StoreUnavailable, database_url

from .settings import Settings

log = logging.getLogger("api.store")


def open_store(settings: Settings) -> Store:
    """The store the settings name: ``SYNTH_DATABASE_URL`` when set, else the SQLite file ``SYNTH_STUDIES_DB``."""
    return Store(database_url(settings.database_url, settings.studies_db))


def migrate_at_start(store: Store) -> None:
    """Bring the store's schema up to date; a migration that fails stops the service with the reason. A store
    that cannot be reached does not: the service starts, ``/ready`` says why, requests needing the store answer
    503, and the migrations run when it is reached."""
    try:
        store.migrate()
    except StoreUnavailable as exc:
        log.error("%s; the service starts without it", exc)
    except MigrationFailed as exc:
        # raised out of the start-up: the server reports the failed start with this reason and exits
        log.critical("the service cannot start: %s", exc)
        raise


def store_status(store: Store) -> dict[str, Any]:
    """The store's engine, whether it answers and whether it takes writes, with the reason when it does not;
    never raises."""
    try:
        store.ping()
    except StoreUnavailable as exc:
        return {"store": store.dialect, "store_ok": False, "store_writable": False, "store_problem": exc.reason}
    except MigrationFailed as exc:
        return {"store": store.dialect, "store_ok": False, "store_writable": False, "store_problem": str(exc)}
    cannot_write = store.write_problem()
    return {"store": store.dialect, "store_ok": True, "store_writable": cannot_write is None,
            "store_problem": cannot_write}


def get_store(request: Request) -> Store:
    """The app's store."""
    store: Store = request.app.state.store
    return store


StoreDep = Annotated[Store, Depends(get_store)]
