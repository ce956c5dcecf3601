# shellcheck shell=bash
# Source me:  source scripts/env.sh   (from any directory)
# Gives a shell where Debian's ROS Python comes first (with the workspace venv for the PyPI
# extras), the workspace overlay is sourced, and ROS binds to localhost unless you set
# ROS_IP / ROS_HOSTNAME / ROS_MASTER_URI yourself.
_modrob_root="$(cd "$(dirname "${BASH_SOURCE[0]:-$0}")/.." && pwd)"
if [ ! -f "$_modrob_root/devel/setup.bash" ] || [ ! -x "$_modrob_root/.venv/bin/python3" ]; then
  echo "modrob: the workspace in $_modrob_root is not built yet." >&2
  echo "        Run 'make setup' there (installs packages, creates .venv, builds), then source this again." >&2
  unset _modrob_root
  return 1 2>/dev/null || exit 1
fi
# Trap 1: the pyenv python3 on PATH has no ROS modules. The venv's python3 is Debian's.
export VIRTUAL_ENV="$_modrob_root/.venv"
case ":$PATH:" in
  *":$VIRTUAL_ENV/bin:/usr/bin:"*) ;;
  *) export PATH="$VIRTUAL_ENV/bin:/usr/bin:$PATH" ;;
esac
# shellcheck disable=SC1091
source "$_modrob_root/devel/setup.bash"
export MODROB_ROOT="$_modrob_root"
# roscd, rosed, ... are shell functions that Debian ships with bash completion.
if [ -n "${BASH_VERSION:-}" ] && ! type roscd >/dev/null 2>&1 && [ -f /usr/share/bash-completion/completions/rosbash ]; then
  # shellcheck disable=SC1091
  source /usr/share/bash-completion/completions/rosbash
fi
if [ -z "${ROS_IP:-}" ] && [ -z "${ROS_HOSTNAME:-}" ]; then
  export ROS_IP=127.0.0.1
fi
export ROS_MASTER_URI="${ROS_MASTER_URI:-http://localhost:11311}"
export PYTHONDONTWRITEBYTECODE=1
unset _modrob_root
