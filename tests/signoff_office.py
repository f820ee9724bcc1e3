"""An office of people on real services (uvicorn, sign-in on) sharing one store, SQLite or PostgreSQL: the first
admin from the settings makes the others and an API token for each, so every request below is made as a person.

Two services on one store stand for an office with two service processes (or two servers)."""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx

from service import running_process

PASSWORD = "correct horse battery"
SESSION_KEY = "k" * 48
#: Who works in the office: an author, a checker, an approver, one who holds both signing roles, a viewer and an
#: admin with no signing role.
PEOPLE = {"ann": ["engineer"], "bob": ["checker"], "cid": ["approver"], "dan": ["checker", "approver", "engineer"],
          "vic": ["viewer"]}
# a machine design is worked out on every save: more than the default deadline on a machine shared with others
DEADLINE_S = "600"


@dataclass
class Office:
    """Services on one store and a client per person (bearer tokens)."""

    urls: list[str]
    people: dict[str, httpx.Client]
    admin: httpx.Client
    stack: ExitStack
    others: dict[tuple[str, int], httpx.Client] = field(default_factory=dict)

    def as_(self, name: str, server: int = 0) -> httpx.Client:
        """The client of ``name`` (its token) on service ``server``."""
        client = self.people[name] if name != "ada" else self.admin
        if server == 0:
            return client
        if (name, server) not in self.others:
            self.others[(name, server)] = self.stack.enter_context(httpx.Client(
                base_url=self.urls[server], headers=dict(client.headers), timeout=client.timeout))
        return self.others[(name, server)]

    def client(self, **kwargs: Any) -> httpx.Client:
        """A client closed with the office."""
        return self.stack.enter_context(httpx.Client(**{"base_url": self.urls[0], "timeout": 60, **kwargs}))

    def sign_in(self, name: str, password: str = PASSWORD) -> httpx.Client:
        """A browser-like client signed in as ``name`` (a session cookie)."""
        browser = self.client()
        r = browser.post("/v1/auth/signin", json={"name": name, "password": password})
        assert r.status_code == 200, r.text
        return browser

    def add_person(self, name: str, roles: list[str]) -> httpx.Client:
        """A new user with ``roles`` and a client holding a token of theirs."""
        r = self.admin.post("/v1/users", json={"name": name, "password": PASSWORD, "roles": roles})
        assert r.status_code == 201, r.text
        return self.token_client(name)

    def token_client(self, name: str) -> httpx.Client:
        """A client holding a new API token of ``name``."""
        token = self.admin.post(f"/v1/users/{name}/tokens", json={"label": "test"})
        assert token.status_code == 201, token.text
        return self.client(headers={"authorization": f"Bearer {token.json()['token']}"}, timeout=600)


@contextmanager
def office(database_url: str, scratch: Path, servers: int = 1) -> Iterator[Office]:
    """``servers`` services on the store at ``database_url`` with sign-in on and :data:`PEOPLE` in it."""
    env = {"SYNTH_AUTH": "on", "SYNTH_DATABASE_URL": database_url, "SYNTH_SESSION_KEY": SESSION_KEY,
           "SYNTH_ADMIN_NAME": "ada", "SYNTH_ADMIN_PASSWORD": PASSWORD, "SYNTH_REQUEST_DEADLINE_S": DEADLINE_S,
           "SYNTH_WORKERS": "1"}

    def command(port: int) -> list[str]:
        return [sys.executable, "-m", "uvicorn", "api.app:app", "--host", "127.0.0.1", "--port", str(port)]

    with ExitStack() as stack:
        # started side by side and stopped side by side: each takes tens of seconds on a busy machine
        launches = [running_process(command, scratch, start_timeout_s=300, env=env) for _ in range(servers)]
        with ThreadPoolExecutor(servers) as pool:
            started = list(pool.map(lambda launch: launch.__enter__(), launches))
        for launch in launches:
            stack.push(launch)
        stack.callback(lambda: [os.killpg(proc.pid, signal.SIGTERM) for _, proc in started if proc.poll() is None])
        urls = [url for url, _ in started]
        browser = stack.enter_context(httpx.Client(base_url=urls[0], timeout=60))
        r = browser.post("/v1/auth/signin", json={"name": "ada", "password": PASSWORD})
        assert r.status_code == 200, r.text
        csrf = {"x-csrf-token": r.json()["csrf_token"]}
        token = browser.post("/v1/users/ada/tokens", json={"label": "admin"}, headers=csrf).json()["token"]
        admin = stack.enter_context(httpx.Client(base_url=urls[0], timeout=600,
                                                 headers={"authorization": f"Bearer {token}"}))
        the_office = Office(urls, {}, admin, stack)
        for name, roles in PEOPLE.items():
            the_office.people[name] = the_office.add_person(name, roles)
        yield the_office


def ok(response: httpx.Response, status: int = 200) -> Any:
    """The JSON of a response that must have ``status``."""
    assert response.status_code == status, (response.status_code, response.text)
    return response.json()
