# Two commands do everything on a fresh machine (Debian/Ubuntu, Python 3.11, as root):
#   make workflow   set up, then run the default workflow (also plain `make`)
#   make test       set up (with Chromium, for the viewers' tests), then run the test suite
# Set-up installs the system library Open3D needs, creates .venv, installs the package with
# every dependency pinned and compiles its kernels; it is skipped when nothing changed.

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
CORES ?= all

.PHONY: workflow test setup system browser
.DEFAULT_GOAL := workflow

workflow: setup
	$(BIN)/snakemake --cores $(CORES)

test: setup browser
	$(BIN)/pytest

setup: system $(STAMP)

# The tests open the interactive viewers in a real browser: Debian's Chromium, headless.
browser:
	@command -v chromium >/dev/null 2>&1 || { apt-get update -qq && apt-get install -y -qq chromium; }

# Open3D's pip wheel links against libusb-1.0.
system:
	@dpkg -s libusb-1.0-0 >/dev/null 2>&1 || { apt-get update -qq && apt-get install -y -qq libusb-1.0-0; }

$(STAMP): pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --disable-pip-version-check -r requirements.lock
	$(BIN)/pip install --quiet --disable-pip-version-check --no-deps -e .
	# FReD's spectra ship in dreye's data; its code and dependencies are not needed.
	$(BIN)/pip install --quiet --disable-pip-version-check --no-deps dreye==1.1.0
	# The tracer's and the relaxation's kernels, compiled once into numba's cache (beeoptics.jit).
	$(BIN)/beeoptics compile-kernels
	touch $@
