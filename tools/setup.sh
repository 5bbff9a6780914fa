#!/usr/bin/env bash
# Sets up drake_car on a fresh Debian/Ubuntu machine: the system packages (Graphviz for the
# Diagram pictures, Chromium for the replay's real-browser test), a virtual environment in
# .venv with drake, numpy, matplotlib, dask, tqdm and the test tools, and the project itself
# (editable). Idempotent: a second run only checks. Usage: bash tools/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
command -v dot >/dev/null 2>&1 || missing+=(graphviz)
command -v chromium >/dev/null 2>&1 || missing+=(chromium)
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing the system packages ${missing[*]}"
  if [ "$(id -u)" = "0" ]; then SUDO=""; elif command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: ERROR: the Debian/Ubuntu packages ${missing[*]} are missing and this user" \
         "cannot install them; install them and run again" >&2
    exit 1
  fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi

PYTHON="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv with $($PYTHON --version)"
  "$PYTHON" -m venv .venv
fi
if ! .venv/bin/python -c "import drake_car, pydrake, pytest, scipy, dask.distributed, tqdm, playwright" \
     >/dev/null 2>&1 || [ pyproject.toml -nt .venv/.drake_car_installed ]; then
  echo "setup: installing drake_car and its dependencies into .venv (first time: a few minutes)"
  .venv/bin/python -m pip install --quiet --upgrade pip
  .venv/bin/python -m pip install --quiet -e ".[test]"
  touch .venv/.drake_car_installed
fi
echo "setup: ready (drake $(.venv/bin/python -c 'import importlib.metadata as m; print(m.version("drake"))'))"
