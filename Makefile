# Two commands for a fresh machine: `make run` serves the API, `make test` runs the whole suite.
# Both create .venv in the repo root when it is missing and reinstall when pyproject.toml changes.
PYTHON ?= python3
VENV := .venv
STAMP := $(VENV)/.installed
HOST ?= 127.0.0.1
PORT ?= 8000
# Optional dependencies installed with the package: the test tools by default; the Docker image sets it empty.
EXTRAS ?= [test]

.PHONY: run test bench lint

$(STAMP): pyproject.toml
	test -x $(VENV)/bin/python || $(PYTHON) -m venv $(VENV)
	$(VENV)/bin/python -m pip install --quiet --upgrade pip
	$(VENV)/bin/python -m pip install --quiet -e '.$(EXTRAS)'
	touch $(STAMP)

run: $(STAMP)
	$(VENV)/bin/python -m api.serve --host $(HOST) --port $(PORT)

# The workbench's browser tests drive Debian's Chromium (Playwright's own download is not used); the store's tests
# start a throwaway PostgreSQL cluster with Debian's server binaries; the design record's drawings are read back
# with poppler's pdftotext.
CHROMIUM := /usr/bin/chromium

test: $(STAMP)
	test -x $(CHROMIUM) || (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends chromium)
	ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1 || (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends postgresql)
	test -x /usr/sbin/nginx || (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends nginx-light)
	test -x /usr/bin/pdftotext || (apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends poppler-utils)
	$(VENV)/bin/python -m mypy
	$(VENV)/bin/python -m pytest -q

bench: $(STAMP)
	$(VENV)/bin/python -m bench
