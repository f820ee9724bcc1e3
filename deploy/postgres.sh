#!/bin/sh
# A PostgreSQL server for the service's store, on this machine, step by step (docs/deployment.md follows it, and
# the tests start their PostgreSQL servers with it).
#
#   deploy/postgres.sh DIR [PORT [SERVER OPTIONS...]]
#
# DIR holds the cluster (DIR/data), its log (DIR/log) and its socket; PORT defaults to 5432. With SYNTH_DB_PASSWORD
# set, the role synth needs that password over TCP (scram-sha-256); without it, loopback connections are trusted
# (a test machine, or a server nobody else logs into). The last line printed is the service's SYNTH_DATABASE_URL.
set -eu
DIR=$1
PORT=${2:-5432}
[ $# -ge 2 ] && shift 2 || shift $#

# 1. Debian's postgresql package puts the server's programs here, one directory per major version: take the newest.
BIN=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1)
[ -n "$BIN" ] || { echo "PostgreSQL is not installed: apt-get install postgresql" >&2; exit 1; }

# 2. The server refuses to run as root ("initdb: cannot be run as root"): as root, every step runs as the postgres
#    user the package made, and the cluster's directory belongs to it.
mkdir -p "$DIR"
if [ "$(id -u)" = 0 ]; then
    chown postgres:postgres "$DIR"
    AS="runuser -u postgres --"
else
    AS=""
fi

# 3. A cluster whose superuser is synth (the service's role), UTF-8; with a password when one is given.
if [ -n "${SYNTH_DB_PASSWORD:-}" ]; then
    PWFILE=$(mktemp)
    printf '%s\n' "$SYNTH_DB_PASSWORD" > "$PWFILE"
    [ -z "$AS" ] || chown postgres "$PWFILE"
    AUTH="--auth-local=trust --auth-host=scram-sha-256 --pwfile=$PWFILE"
else
    PWFILE=""
    AUTH="--auth=trust"
fi
# shellcheck disable=SC2086
$AS "$BIN/initdb" -D "$DIR/data" -U synth $AUTH -E UTF8 --no-locale ${SYNTH_INITDB_OPTIONS:-} >"$DIR/initdb.log"
[ -z "$PWFILE" ] || rm -f "$PWFILE"

# 4. Started on loopback only, its socket in DIR; -w waits until it takes connections.
$AS "$BIN/pg_ctl" -D "$DIR/data" -l "$DIR/log" -w \
    -o "-p $PORT -k $DIR -c listen_addresses=127.0.0.1 $*" start >/dev/null

# 5. The service's database.
$AS "$BIN/createdb" -h "$DIR" -p "$PORT" -U synth synth

if [ -n "${SYNTH_DB_PASSWORD:-}" ]; then
    echo "SYNTH_DATABASE_URL=postgresql://synth:PASSWORD@127.0.0.1:$PORT/synth"
else
    echo "SYNTH_DATABASE_URL=postgresql://synth@127.0.0.1:$PORT/synth"
fi
