#!/usr/bin/env bash
# Regenerates the lock files requirements/py3.11.txt, py3.12.txt and py3.13.txt (one per
# supported Python) from pyproject.toml with its `test` extra and the install tools (pip, and
# setuptools to build the editable install: requirements/install-tools.in), every package at
# the newest version they allow. tools/setup.sh installs with the lock file of its Python as
# constraints, so a fresh machine gets exactly the versions CI passed with.
#
#   bash tools/upgrade_locks.sh [EXTRA uv pip compile OPTIONS, e.g. --exclude-newer 2026-12-01]
#
# Before committing the upgraded set: CI must pass on it (bash .ci/run on a fresh clone:
# the whole suite on the newest drake, the quick tier on drake 1.51) -- a lock file is a
# promise that these versions work, not a guess.
#
# The resolver is uv (`uv pip compile`, which resolves for any Python version without that
# Python installed); $UV or a `uv` on PATH is used, else uv $UV_VERSION is installed into a
# throwaway venv outside the repository ($LOCK_VENV, default ${TMPDIR:-/tmp}/drake_car-lockvenv).
# The files are for Linux x86_64 (drake's wheels there are manylinux_2_34: glibc >= 2.34).
# All three are written or none (a failed resolution leaves the old files as they were).
set -euo pipefail
cd "$(dirname "$0")/.."

UV_VERSION="${UV_VERSION:-0.13.9}"
PYTHONS=(3.11 3.12 3.13)
PLATFORM="x86_64-manylinux_2_34"

uv="${UV:-}"
if [ -z "$uv" ] && command -v uv >/dev/null 2>&1; then uv="$(command -v uv)"; fi
if [ -z "$uv" ]; then
  venv="${LOCK_VENV:-${TMPDIR:-/tmp}/drake_car-lockvenv}"
  if [ ! -x "$venv/bin/uv" ]; then
    echo "upgrade_locks: installing uv $UV_VERSION into $venv"
    python3 -m venv "$venv"
    "$venv/bin/python" -m pip install --quiet "uv==$UV_VERSION"
  fi
  uv="$venv/bin/uv"
fi
uv_version="$("$uv" --version | awk '{print $2}')"

tmp="$(mktemp -d requirements.tmp-XXXXXX)"
trap 'rm -rf "$tmp"' EXIT
for v in "${PYTHONS[@]}"; do
  out="requirements/py$v.txt"
  compile=(uv pip compile pyproject.toml requirements/install-tools.in --extra test
           --python-version "$v" --python-platform "$PLATFORM" --no-header --quiet "$@")
  {
    echo "# $out: the exact versions of drake_car's dependencies (with the test extra) and"
    echo "# install tools that CI passed with on Python $v, Linux x86_64. tools/setup.sh installs"
    echo "# with it as constraints: pip install -c $out -e \".[test]\"."
    echo "# Regenerate all lock files (then CI must pass before committing them):"
    echo "#   bash tools/upgrade_locks.sh"
    echo "# which ran, with uv $uv_version:"
    echo "#   ${compile[*]}"
    "$uv" "${compile[@]:1}"
  } > "$tmp/py$v.txt"
  echo "upgrade_locks: $out: drake $(grep -E '^drake==' "$tmp/py$v.txt" | cut -d= -f3)," \
       "$(grep -cE '^[a-zA-Z0-9]' "$tmp/py$v.txt") packages"
done
mkdir -p requirements
for v in "${PYTHONS[@]}"; do mv "$tmp/py$v.txt" "requirements/py$v.txt"; done
git --no-pager diff --stat -- requirements 2>/dev/null || true
echo "upgrade_locks: done; now run CI (bash .ci/run) on the new set before committing it"
