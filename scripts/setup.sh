#!/usr/bin/env bash
# Sets up a Debian 12 machine (as root) for surfkit, then runs the command given, if any:
#   bash scripts/setup.sh bash scripts/test.sh
# Installs, only when missing: a C++ compiler, pkg-config and CMake (the C++ examples'
# tests), libclang (for bindgen), Chromium and its chromedriver (the HTML reports' browser
# tests), OpenMesh
# (libopenmesh-dev), OpenSubdiv (libosd-dev), CGAL headers (libcgal-dev, cross-checks),
# a Rust toolchain (rustup) when cargo is not on PATH, and in .venv the Python peers the
# cross-checks and benches compare with (pymeshlab, trimesh, numpy, scipy) and what the Python
# package needs to build and test (maturin, pytest, ruff; dask, pandas and pyarrow for its
# corpus scans; selenium and pillow for the browser tests); the command finds it through
# SURFKIT_PYTHON.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
cd "$(dirname "$0")/.."

packages=(build-essential pkg-config cmake libclang-dev libopenmesh-dev libosd-dev libcgal-dev
          python3 python3-venv python3-pip ca-certificates curl chromium chromium-driver)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "surfkit setup: installing ${missing[*]}" >&2
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ! command -v cargo >/dev/null 2>&1; then
  if [ -f "$HOME/.cargo/env" ]; then
    . "$HOME/.cargo/env"
  else
    echo "surfkit setup: installing the Rust toolchain with rustup" >&2
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal
    . "$HOME/.cargo/env"
  fi
fi

if [ ! -x .venv/bin/python ] || [ ! -x .venv/bin/maturin ] || [ ! -x .venv/bin/ruff ] ||
   ! .venv/bin/python -c 'import pymeshlab, trimesh, numpy, scipy, pytest, distributed, pandas, pyarrow, selenium, PIL' >/dev/null 2>&1; then
  echo "surfkit setup: installing pymeshlab, trimesh, numpy, scipy, pytest, maturin, ruff, dask, pandas, pyarrow, selenium and pillow into .venv" >&2
  /usr/bin/python3 -m venv .venv 2>/dev/null || python3 -m venv .venv
  .venv/bin/python -m pip install -q --disable-pip-version-check pymeshlab trimesh numpy scipy \
    pytest "maturin==1.16.0" "ruff==0.17.6" "dask[distributed]" pandas pyarrow selenium pillow
fi
export SURFKIT_PYTHON="$PWD/.venv/bin/python"

if [ $# -gt 0 ]; then
  exec "$@"
fi
