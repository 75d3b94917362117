# Workcell developer entry points. `make run` and `make test` are all you need:
# both create/refresh the virtualenv in .venv automatically.

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := run

PYTHON ?= $(shell command -v python3.11 2>/dev/null || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.stamp
UVTOOL ?= /tmp/uvtool

# Offscreen rendering through EGL (Mesa llvmpipe on machines without a GPU).
MUJOCO_GL ?= egl
export MUJOCO_GL

.PHONY: setup run test lock bench

setup: $(STAMP)

# Reinstalls only when the lock file or pyproject.toml is newer than the stamp.
$(STAMP): requirements.lock pyproject.toml
	@if [ ! -x $(BIN)/python ]; then \
	  $(PYTHON) -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' \
	    || { echo "error: Python 3.11 is required ($(PYTHON) is $$($(PYTHON) -V 2>&1))" >&2; exit 1; }; \
	  echo "creating $(VENV)"; \
	  $(PYTHON) -m venv $(VENV); \
	fi
	@echo "installing dependencies into $(VENV)"
	@$(BIN)/pip install -q --disable-pip-version-check --require-hashes -r requirements.lock
	@$(BIN)/pip install -q --disable-pip-version-check --no-deps --no-build-isolation -e .
	@touch $(STAMP)

include web/web.mk

# The main job: the web app on http://127.0.0.1:8000 (setup, teleop, sessions, replay),
# recording into the embedded SQLite store workcell.sqlite.
run: setup web-setup
	$(BIN)/workcell serve

# Static checks (Python and strict TypeScript), then the whole test suite including the
# browser tests in Debian's chromium; stops at the first failing step.
test: setup web-setup browser-setup
	$(BIN)/ruff check src tests bench
	$(BIN)/ruff format --check src tests bench
	$(BIN)/mypy
	$(BIN)/python -m workcell.protocol.typescript --check
	WORKCELL_BROWSER_TESTS=require $(BIN)/pytest -n 2

bench: setup
	$(BIN)/python bench/sim.py
	$(BIN)/python bench/record.py

# Regenerates requirements.lock (runtime + dev + build backend, hashed) for
# CPython 3.11 on linux x86_64. Existing pins are kept unless pyproject.toml
# forces a change; use `make lock LOCK_ARGS=--upgrade` to move everything.
LOCK_ARGS ?=
lock:
	@[ -x $(UVTOOL)/bin/uv ] || { python3 -m venv $(UVTOOL) && $(UVTOOL)/bin/pip install -q uv; }
	@tmp=$$(mktemp); \
	{ [ -f requirements.lock ] && cp requirements.lock $$tmp; } || true; \
	printf "hatchling\neditables\n" | $(UVTOOL)/bin/uv pip compile pyproject.toml - \
	  --extra dev --generate-hashes --python-version 3.11 \
	  --python-platform x86_64-unknown-linux-gnu \
	  --custom-compile-command "make lock" -q $(LOCK_ARGS) -o $$tmp; \
	{ echo "# Pinned, hashed dependencies of Workcell (runtime + dev extra + hatchling build"; \
	  echo "# backend) for CPython 3.11 on linux x86_64. Do not edit by hand: change"; \
	  echo "# pyproject.toml, then regenerate with \`make lock\`."; \
	  grep -v -e '^# Pinned, hashed' -e '^# backend) for' -e '^# pyproject.toml, then' $$tmp; } > requirements.lock; \
	rm -f $$tmp
	@echo "requirements.lock updated"
