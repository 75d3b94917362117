# The web client (web/): included by the top-level Makefile (`include web/web.mk`).
#
#   make web-setup       npm ci + npm run build (type check, then Vite) into web/dist;
#                        reinstalls only when package.json/package-lock.json change and
#                        rebuilds only when a source changed (stamps)
#   make browser-setup   Debian's chromium for the browser tests (root; CI)
#   make web-typecheck   strict TypeScript check only
#   make web-test        the client's unit tests (vitest) and the e2e scripts' compile
#   make web-e2e URL=http://127.0.0.1:8000
#                        the browser end-to-end scripts against a running `workcell serve`
#
# The browser tests proper run from pytest (tests/web/test_browser.py), which starts the
# server itself; they skip without chromium or a built client unless
# WORKCELL_BROWSER_TESTS=require.

WEB_DIR        := web
WEB_DEPS_STAMP := $(WEB_DIR)/node_modules/.workcell-deps.stamp
WEB_DIST_STAMP := $(WEB_DIR)/dist/.workcell-build.stamp
WEB_SOURCES    := $(shell find $(WEB_DIR)/src $(WEB_DIR)/tests/unit -type f 2>/dev/null) \
                  $(WEB_DIR)/index.html $(WEB_DIR)/vite.config.ts $(WEB_DIR)/tsconfig.json
CHROMIUM       ?= /usr/bin/chromium

.PHONY: web-setup web-typecheck web-test web-e2e browser-setup

web-setup: $(WEB_DIST_STAMP)

$(WEB_DEPS_STAMP): $(WEB_DIR)/package.json $(WEB_DIR)/package-lock.json
	@command -v npm >/dev/null || { echo "error: npm is required for the web client (install Node.js 20.19+)" >&2; exit 1; }
	@echo "installing web client dependencies (npm ci)"
	@cd $(WEB_DIR) && npm ci --no-audit --no-fund --loglevel=error
	@touch $@

$(WEB_DIST_STAMP): $(WEB_DEPS_STAMP) $(WEB_SOURCES)
	@echo "building the web client into $(WEB_DIR)/dist"
	@cd $(WEB_DIR) && npm run --silent build
	@touch $@

web-typecheck: $(WEB_DEPS_STAMP)
	@cd $(WEB_DIR) && npm run --silent typecheck

URL ?= http://127.0.0.1:8000
web-e2e: $(WEB_DIST_STAMP)
	@cd $(WEB_DIR) && npm run --silent build:e2e && for script in xr_delivery desktop_delivery sessions_replay; do \
	  node build/e2e/tests/e2e/$$script.js $(URL) || exit 1; \
	done

# The client's unit tests (vitest) and the strict type check of the end-to-end scripts.
web-test: $(WEB_DEPS_STAMP)
	@cd $(WEB_DIR) && npm run --silent test:unit && npm run --silent build:e2e

browser-setup:
	@if [ -x $(CHROMIUM) ]; then \
	  echo "chromium present: $$($(CHROMIUM) --version 2>/dev/null || echo $(CHROMIUM))"; \
	elif [ "$$(id -u)" -ne 0 ]; then \
	  echo "error: $(CHROMIUM) is missing; as root run: apt-get install chromium" >&2; exit 1; \
	else \
	  echo "installing Debian chromium"; \
	  export DEBIAN_FRONTEND=noninteractive; \
	  apt-get update -qq && apt-get install -y -qq chromium; \
	fi
