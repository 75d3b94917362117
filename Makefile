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

.PHONY: setup setup-learn run test lock bench

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

# The learn extra (LeRobot and torch, several GB) for the learning tests and `workcell
# train`: installed by `make test`, never by `make run`. Same versions as requirements.lock
# for every package the two share, so it only adds packages to the virtualenv.
LEARN_STAMP := $(VENV)/.learn-stamp

setup-learn: $(LEARN_STAMP)

$(LEARN_STAMP): $(STAMP) requirements-learn.lock
	@echo "installing the learn extra (LeRobot, torch) into $(VENV)"
	@$(BIN)/pip install -q --disable-pip-version-check --require-hashes -r requirements-learn.lock
	@touch $@

include web/web.mk

# The main job: the web app on http://127.0.0.1:8000 (setup, teleop, sessions, replay),
# recording into the embedded SQLite store workcell.sqlite.
run: setup web-setup
	$(BIN)/workcell serve

# Static checks (Python and strict TypeScript), the web client's unit tests, then the
# whole test suite including the browser tests in Debian's chromium and the learning tests (LeRobot); stops at the first
# failing step. The two workers take whole files, longest first, and the browser files all
# on one worker (tests/conftest.py orders them and schedules them together), so each
# file's fixtures are built once, no worker waits on the browser lock and none idles
# beside a long file.
test: setup setup-learn web-setup browser-setup
	$(BIN)/ruff check src tests bench examples
	$(BIN)/ruff format --check src tests bench examples
	$(BIN)/mypy
	$(BIN)/python -m workcell.protocol.typescript --check
	@$(MAKE) --no-print-directory web-test
	WORKCELL_BROWSER_TESTS=require WORKCELL_LEARN_TESTS=require $(BIN)/pytest -n 2 --dist loadfile --no-loadscope-reorder

bench: setup
	$(BIN)/python bench/sim.py
	$(BIN)/python bench/record.py

# Regenerates both lock files (hashed, for CPython 3.11 on linux x86_64).
# requirements-learn.lock (runtime + dev + learn extras + build backend) is resolved
# first, then requirements.lock (runtime + dev + build backend) within its pins, so every
# package has one version in both and `make test` adds the learn extra to the same
# virtualenv. Existing pins are kept unless pyproject.toml forces a change; use
# `make lock LOCK_ARGS=--upgrade` to move everything.
LOCK_ARGS ?=
define compile_lock
	tmp=$$(mktemp); \
	{ [ -f $(1) ] && cp $(1) $$tmp; } || { [ -f requirements.lock ] && cp requirements.lock $$tmp; } || true; \
	printf "hatchling\neditables\n" | $(UVTOOL)/bin/uv pip compile pyproject.toml - \
	  $(2) --generate-hashes --python-version 3.11 \
	  --python-platform x86_64-unknown-linux-gnu \
	  --custom-compile-command "make lock" -q $(LOCK_ARGS) -o $$tmp; \
	{ echo "# Pinned, hashed dependencies of Workcell ($(3)) for CPython 3.11 on"; \
	  echo "# linux x86_64. Do not edit by hand: change pyproject.toml, then regenerate"; \
	  echo "# with \`make lock\`."; \
	  grep -v -e '^# Pinned, hashed' -e '^# linux x86_64. Do not' -e '^# with `make lock`' $$tmp; } > $(1); \
	rm -f $$tmp
endef
lock:
	@[ -x $(UVTOOL)/bin/uv ] || { python3 -m venv $(UVTOOL) && $(UVTOOL)/bin/pip install -q uv; }
	@$(call compile_lock,requirements-learn.lock,--extra dev --extra learn,runtime + dev + learn extras + hatchling build backend)
	@$(call compile_lock,requirements.lock,--extra dev -c requirements-learn.lock,runtime + dev extra + hatchling build backend)
	@echo "requirements.lock and requirements-learn.lock updated"
