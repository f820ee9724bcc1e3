"""Users and API tokens from the command line, in the store the service's settings name (the admin's bootstrap).

    python -m api.users add ada --role admin            # asks for the password twice
    echo "$PASSWORD" | python -m api.users add ada --role engineer --password-stdin
    python -m api.users token ada --label "nightly studies"   # prints a new API token once
    python -m api.users list
    python -m api.users roles ada --role viewer
    python -m api.users passwd ada
    python -m api.users remove ada
"""

from __future__ import annotations

import argparse
import getpass
import sys

import sqlalchemy as sa

from .auth.roles import ROLES
from .auth import passwords, tokens
from .auth.users import Accounts
from .settings import Settings
from .storage import open_store

ROLE_NAMES = list(ROLES)


def _password(args: argparse.Namespace) -> str:
    if args.password_stdin:
        password = sys.stdin.readline().rstrip("\n")
    else:
        password = getpass.getpass("password: ")
        if getpass.getpass("again: ") != password:
            raise SystemExit("the passwords differ")
    if not passwords.MIN_LENGTH <= len(password) <= passwords.MAX_LENGTH:
        raise SystemExit(f"a password has {passwords.MIN_LENGTH} to {passwords.MAX_LENGTH} characters")
    return password


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m api.users", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    add = sub.add_parser("add", help="make a user")
    add.add_argument("name")
    add.add_argument("--role", action="append", choices=ROLE_NAMES, required=True, help="repeat for several")
    add.add_argument("--password-stdin", action="store_true", help="read the password from standard input")
    token = sub.add_parser("token", help="make an API token for a user and print it")
    token.add_argument("name")
    token.add_argument("--label", default="command line")
    sub.add_parser("list", help="every user and its roles")
    roles = sub.add_parser("roles", help="set a user's roles")
    roles.add_argument("name")
    roles.add_argument("--role", action="append", choices=ROLE_NAMES, required=True)
    passwd = sub.add_parser("passwd", help="set a user's password")
    passwd.add_argument("name")
    passwd.add_argument("--password-stdin", action="store_true")
    remove = sub.add_parser("remove", help="remove a user and its tokens")
    remove.add_argument("name")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command against the store of ``SYNTH_DATABASE_URL`` or ``SYNTH_STUDIES_DB``."""
    args = _parser().parse_args(argv)
    store = open_store(Settings.from_env())
    store.migrate()
    accounts = Accounts(store)
    try:
        if args.command == "list":
            for each in accounts.all():
                print(f"{each.name}\t{' '.join(sorted(each.roles))}")
            return 0
        if args.command == "add":
            try:
                accounts.create(args.name, set(args.role), passwords.hash_password(_password(args)))
            except sa.exc.IntegrityError:
                raise SystemExit(f"a user named {args.name!r} exists already") from None
            print(f"made {args.name} ({', '.join(sorted(set(args.role)))})")
            return 0
        user = accounts.by_name(args.name)
        if user is None:
            raise SystemExit(f"no user is named {args.name!r}")
        if args.command == "token":
            token = tokens.new_token()
            accounts.add_token(user.id, token, args.label)
            print(token)
        elif args.command == "roles":
            accounts.set_roles(user.id, set(args.role))
        elif args.command == "passwd":
            accounts.set_password_hash(user.id, passwords.hash_password(_password(args)))
            accounts.end_credentials(user.id)
        elif args.command == "remove":
            accounts.remove(user)
        return 0
    finally:
        store.dispose()


if __name__ == "__main__":
    sys.exit(main())
