#!/usr/bin/env bash
# Sets up drake_car on a fresh machine: Graphviz (for the diagram picture), a virtual
# environment in .venv with drake, numpy, matplotlib and the test tools. Idempotent: a second
# run only checks. Usage: bash tools/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v dot >/dev/null 2>&1; then
  echo "setup: installing Graphviz (dot) for the diagram pictures"
  if [ "$(id -u)" = "0" ]; then SUDO=""; elif command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: ERROR: Graphviz's 'dot' is missing and this user cannot install it; install the" \
         "Debian/Ubuntu package 'graphviz' and run again" >&2
    exit 1
  fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq graphviz >/dev/null
fi

PYTHON="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv with $($PYTHON --version)"
  "$PYTHON" -m venv .venv
fi
if ! .venv/bin/python -c "import drake_car, pydrake, pytest, scipy" >/dev/null 2>&1 \
   || [ pyproject.toml -nt .venv/.drake_car_installed ]; then
  echo "setup: installing drake_car and its dependencies into .venv (first time: a few minutes)"
  .venv/bin/python -m pip install --quiet --upgrade pip
  .venv/bin/python -m pip install --quiet -e ".[test]"
  touch .venv/.drake_car_installed
fi
echo "setup: ready (drake $(.venv/bin/python -c 'import importlib.metadata as m; print(m.version("drake"))'))"
