#!/usr/bin/env bash
# Idempotent set-up of the modrob workspace on Debian bookworm:
#   1. the Debian packages in scripts/debian-packages.txt (only what is missing; one apt-get update),
#   2. .venv (Debian's /usr/bin/python3, --system-site-packages) with the pinned requirements.txt,
#   3. catkin_make of the workspace.
# Re-running it when nothing changed takes seconds.
#
#   scripts/setup.sh            everything
#   scripts/setup.sh --no-build packages and venv only
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=1
[ "${1:-}" = "--no-build" ] && build=0

say() { printf '[setup] %s\n' "$*"; }

# --- 1. Debian packages -------------------------------------------------------------------
mapfile -t wanted < <(sed -e 's/#.*//' -e '/^\s*$/d' "$root/scripts/debian-packages.txt")
missing=()
for p in "${wanted[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${#missing[@]} Debian packages: ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  say "Debian packages: all ${#wanted[@]} present"
fi

# --- 2. virtual environment for the PyPI extras -------------------------------------------
venv="$root/.venv"
if [ ! -x "$venv/bin/python3" ]; then
  say "creating $venv (Debian python3 with system site packages)"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
stamp="$venv/.requirements.sha256"
want_sha=$(sha256sum "$root/requirements.txt" | cut -d' ' -f1)
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want_sha" ]; then
  say "installing pinned PyPI extras from requirements.txt"
  "$venv/bin/python3" -m pip install --quiet --disable-pip-version-check -r "$root/requirements.txt"
  # PyPI's xacro 1.13 came from requirements.txt before the workspace had its own (src/xacro,
  # Noetic's 1.14): an old venv's copy would shadow it outside the workspace environment.
  if "$venv/bin/python3" -m pip show --quiet xacro >/dev/null 2>&1; then
    "$venv/bin/python3" -m pip uninstall --quiet --yes xacro
  fi
  echo "$want_sha" > "$stamp"
else
  say "PyPI extras: up to date"
fi

# --- 3. build ------------------------------------------------------------------------------
if [ "$build" -eq 1 ]; then
  "$root/scripts/build.sh"
fi
say "done. Next: source scripts/env.sh"
