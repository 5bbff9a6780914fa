#!/usr/bin/env bash
# Sets up drake_car on a fresh Debian/Ubuntu machine: the system packages (Graphviz for the
# Diagram pictures, Chromium for the replay's real-browser test), a virtual environment in
# .venv with drake, numpy, matplotlib, dask, tqdm and the test tools, and the project itself
# (editable). Idempotent: a second run only checks. Usage: bash tools/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

# A Python drake 1.51 has wheels for: 3.10-3.12 (python3, else python3.12/3.11/3.10, or $PYTHON).
pick_python() {
  for candidate in "${PYTHON:-}" python3 python3.12 python3.11 python3.10; do
    [ -n "$candidate" ] || continue
    if command -v "$candidate" >/dev/null 2>&1 && "$candidate" -c \
        'import sys; sys.exit(0 if (3, 10) <= sys.version_info[:2] <= (3, 12) else 1)' 2>/dev/null; then
      echo "$candidate"; return 0
    fi
  done
  return 1
}

apt_install() {  # apt_install PACKAGE...: as root, or with sudo; fails when neither is possible
  if [ "$(id -u)" = "0" ]; then SUDO=""; elif command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: cannot install the Debian/Ubuntu packages $* as this user" >&2
    return 1
  fi
  $SUDO apt-get update -qq && \
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "$@" >/dev/null
}

if [ ! -x .venv/bin/python ]; then
  PY="$(pick_python)" || {
    echo "setup: ERROR: drake 1.51 needs Python 3.10-3.12; none found (python3 is" \
         "$(python3 --version 2>&1)); install one, or set PYTHON=/path/to/python3.11" >&2
    exit 1
  }
fi

# Graphviz draws the Diagram (needed); Chromium runs the replay's real-browser test (needed in
# CI, where that test must run; elsewhere the test is skipped without it); venv for a Python
# whose venv module is a separate package (Debian's python3.X-venv).
if ! command -v dot >/dev/null 2>&1; then
  echo "setup: installing graphviz"
  apt_install graphviz || { echo "setup: ERROR: install graphviz and run again" >&2; exit 1; }
fi
if ! command -v chromium >/dev/null 2>&1; then
  echo "setup: installing chromium (the replay's browser test)"
  if ! apt_install chromium; then
    if [ -n "${CI:-}" ]; then
      echo "setup: ERROR: CI needs chromium for the browser test" >&2; exit 1
    fi
    echo "setup: WARNING: no chromium: tests/test_replay_browser.py will be skipped" >&2
  fi
fi
if [ ! -x .venv/bin/python ] && ! "$PY" -c "import ensurepip" >/dev/null 2>&1; then
  version="$("$PY" -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
  echo "setup: installing python${version}-venv"
  apt_install "python${version}-venv" || {
    echo "setup: ERROR: $PY has no venv module; install python${version}-venv" >&2; exit 1; }
fi

if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv with $($PY --version)"
  "$PY" -m venv .venv
fi
if ! .venv/bin/python -c "import drake_car, pydrake, pytest, scipy, dask.distributed, tqdm, playwright" \
     >/dev/null 2>&1 || [ pyproject.toml -nt .venv/.drake_car_installed ]; then
  echo "setup: installing drake_car and its dependencies into .venv (first time: a few minutes)"
  .venv/bin/python -m pip install --quiet --upgrade pip
  .venv/bin/python -m pip install --quiet -e ".[test]"
  touch .venv/.drake_car_installed
fi
echo "setup: ready (drake $(.venv/bin/python -c 'import importlib.metadata as m; print(m.version("drake"))'))"
