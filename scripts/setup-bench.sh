#!/usr/bin/env bash
# Installs the Python peers that benches and cross-checks compare surfkit with (trimesh,
# numpy, pymeshlab) into .venv, then runs the command given, if any:
#   bash scripts/setup-bench.sh cargo bench --bench mesh_load
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
export DEBIAN_FRONTEND=noninteractive
if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
  apt-get update -qq && apt-get install -y -qq python3-venv >/dev/null
fi
[ -x .venv/bin/python ] || python3 -m venv .venv
.venv/bin/python -m pip install -q --disable-pip-version-check trimesh numpy pymeshlab
export SURFKIT_PYTHON="$PWD/.venv/bin/python"
[ -f "$HOME/.cargo/env" ] && . "$HOME/.cargo/env"
if [ $# -gt 0 ]; then exec "$@"; fi
