#!/usr/bin/env bash
# Sets up drake_car on a fresh Debian/Ubuntu machine: the system packages (Graphviz for the
# Diagram pictures, Chromium for the replay's real-browser test), a virtual environment with
# drake, numpy, matplotlib, dask, tqdm and the test tools, and the project itself (editable).
#
#   bash tools/setup.sh               .venv: the newest Python >= 3.12 found, with the newest
#                                     drake (falls back to Python 3.11 and drake 1.51)
#   bash tools/setup.sh --drake-1.51  .venv-1.51: Python 3.11 with drake 1.51 (the last drake
#                                     for 3.11; CI runs the quick tier on it). Also: DRAKE_CAR_ENV=1.51
#
# Which Python: $PYTHON (for .venv; $PYTHON_1_51 for .venv-1.51) if set; else python3 if it
# qualifies; else pyenv's installed versions, newest first; else python3.13, python3.12 (for
# the fallback python3.11) on PATH. Only a Python with a lock file qualifies (3.11-3.13:
# requirements/pyX.Y.txt); an existing venv is kept while its Python qualifies and $PYTHON
# does not ask for another one.
#
# Installs with the lock file of its Python as constraints (pip install -c requirements/pyX.Y.txt
# -e ".[test]"): a fresh machine gets exactly the versions CI passed with, and the check at the
# end says so. Idempotent: a second run only checks; it re-installs when pyproject.toml or the
# lock file is newer than the venv's stamp, or the venv does not match the lock file.
set -euo pipefail
cd "$(dirname "$0")/.."

env_name=main
case "${1:-}" in
  "") ;;
  --drake-1.51) env_name=1.51 ;;
  -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
  *) echo "setup: unknown option '$1' (usage: bash tools/setup.sh [--drake-1.51])" >&2; exit 2 ;;
esac
if [ "${DRAKE_CAR_ENV:-}" = "1.51" ]; then env_name=1.51; fi

if [ "$env_name" = 1.51 ]; then
  VENV=.venv-1.51; PREFERRED="3.11"; FALLBACK=""; OVERRIDE="${PYTHON_1_51:-}"; OVERRIDE_NAME=PYTHON_1_51
else
  VENV=.venv; PREFERRED="3.13 3.12"; FALLBACK="3.11"; OVERRIDE="${PYTHON:-}"; OVERRIDE_NAME=PYTHON
fi

py_version() {  # py_version PYTHON: its X.Y, or fails (missing, or a shim that does not run)
  "$1" -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null
}

candidates() {  # the Pythons to try, in order of preference
  echo python3
  local root
  root="$(pyenv root 2>/dev/null || echo "${PYENV_ROOT:-$HOME/.pyenv}")"
  if [ -d "$root/versions" ]; then
    # shellcheck disable=SC2012
    ls -1 "$root/versions" | grep -E '^3\.[0-9]+\.[0-9]+$' | sort -rV |
      while read -r v; do echo "$root/versions/$v/bin/python"; done
  fi
  echo python3.13; echo python3.12; echo python3.11
}

pick_python() {  # pick_python "X.Y X.Y ...": the first candidate whose version is listed
  local c v
  for c in $(candidates); do
    v="$(py_version "$c")" || continue
    case " $1 " in *" $v "*) echo "$c"; return 0 ;; esac
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

# -- which Python ------------------------------------------------------------------------------
venv_version="$(py_version "$VENV/bin/python")" || venv_version=""
PY=""
if [ -n "$OVERRIDE" ]; then
  ver="$(py_version "$OVERRIDE")" || { echo "setup: ERROR: $OVERRIDE_NAME=$OVERRIDE does not run" >&2; exit 1; }
  case " $PREFERRED $FALLBACK " in *" $ver "*) ;; *)
    echo "setup: ERROR: $OVERRIDE_NAME=$OVERRIDE is Python $ver; $VENV needs one of:" \
         "$PREFERRED $FALLBACK" >&2; exit 1 ;;
  esac
  PY="$OVERRIDE"
elif [ -n "$venv_version" ] && case " $PREFERRED " in *" $venv_version "*) true ;; *) false ;; esac; then
  ver="$venv_version"                        # the venv's Python qualifies: keep it
else
  if PY="$(pick_python "$PREFERRED")"; then :
  elif [ -n "$FALLBACK" ] && PY="$(pick_python "$FALLBACK")"; then
    echo "setup: WARNING: no Python $PREFERRED found; $VENV gets Python $FALLBACK and drake 1.51" >&2
  else
    echo "setup: ERROR: $VENV needs Python ${PREFERRED// / or }${FALLBACK:+ (or $FALLBACK)}; none" \
         "found (python3 is $(python3 --version 2>&1)); install one, or set $OVERRIDE_NAME" >&2
    exit 1
  fi
  ver="$(py_version "$PY")"
fi
LOCK="requirements/py$ver.txt"
[ -f "$LOCK" ] || { echo "setup: ERROR: no lock file $LOCK for Python $ver" >&2; exit 1; }
if [ -n "$venv_version" ] && [ "$venv_version" != "$ver" ]; then
  echo "setup: $VENV has Python $venv_version; recreating it with Python $ver"
  rm -rf "$VENV"
fi

# -- system packages ---------------------------------------------------------------------------
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
if [ ! -x "$VENV/bin/python" ] && ! "$PY" -c "import ensurepip" >/dev/null 2>&1; then
  echo "setup: installing python${ver}-venv"
  apt_install "python${ver}-venv" || {
    echo "setup: ERROR: $PY has no venv module; install python${ver}-venv" >&2; exit 1; }
fi

# -- the venv ----------------------------------------------------------------------------------
if [ ! -x "$VENV/bin/python" ]; then
  echo "setup: creating $VENV with $("$PY" --version) ($PY)"
  "$PY" -m venv "$VENV"
fi

matches_lock() {  # the venv holds exactly the lock file's versions (extra packages: a warning)
  "$VENV/bin/python" -I - "$LOCK" "$PWD" <<'EOF'
import importlib.metadata as md, os, re, sys
lock, root = sys.argv[1], sys.argv[2]
norm = lambda name: re.sub(r"[-_.]+", "-", name).lower()
locked = {}
for line in open(lock):
    m = re.match(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==([^\s;#]+)", line)
    if m:
        locked[norm(m[1])] = m[2]
installed = {norm(d.metadata["Name"]): d.version for d in md.distributions()}
wrong = [f"{n} {installed.get(n, 'missing')} (locked {v})" for n, v in sorted(locked.items())
         if installed.get(n) != v]
extra = sorted(set(installed) - set(locked) - {"drake-car"})
try:
    import drake_car
    here = os.path.dirname(os.path.abspath(drake_car.__file__)) == os.path.join(root, "drake_car")
except ImportError:
    here = False
if extra:
    print(f"setup: WARNING: not in {lock}: {', '.join(extra)}", file=sys.stderr)
if wrong:
    print(f"setup: differs from {lock}: {'; '.join(wrong)}", file=sys.stderr)
if not here:
    print("setup: drake_car is not installed (editable) from this checkout", file=sys.stderr)
sys.exit(0 if here and not wrong else 1)
EOF
}

stamp="$VENV/.drake_car_installed"
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ] || [ "$LOCK" -nt "$stamp" ] \
    || ! matches_lock 2>/dev/null; then
  echo "setup: installing drake_car and its dependencies into $VENV from $LOCK" \
       "(first time: a few minutes)"
  rm -f "$stamp"
  # pip and setuptools (the build backend) first, at their locked versions; then the project,
  # built with that setuptools (no isolated build environment fetching an unpinned one).
  "$VENV/bin/python" -m pip install --quiet -c "$LOCK" pip setuptools
  "$VENV/bin/python" -m pip install --quiet --no-build-isolation -c "$LOCK" -e ".[test]"
  matches_lock || { echo "setup: ERROR: $VENV does not match $LOCK after installing" >&2; exit 1; }
  touch "$stamp"
fi
echo "setup: ready: $VENV (Python $("$VENV/bin/python" -c 'import platform; print(platform.python_version())')," \
     "drake $("$VENV/bin/python" -c 'import importlib.metadata as m; print(m.version("drake"))');" \
     "exactly $LOCK)"
