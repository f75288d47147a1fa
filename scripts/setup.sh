#!/usr/bin/env bash
# Sets up a Debian 12 machine (as root) for surfkit, then runs the command given, if any:
#   bash scripts/setup.sh cargo test --release
# Installs, only when missing: a C++ compiler, libclang (for bindgen), OpenMesh
# (libopenmesh-dev), OpenSubdiv (libosd-dev), CGAL headers (libcgal-dev, cross-checks),
# and a Rust toolchain (rustup) when cargo is not on PATH.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive

packages=(build-essential pkg-config libclang-dev libopenmesh-dev libosd-dev libcgal-dev ca-certificates curl)
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

if [ $# -gt 0 ]; then
  cd "$(dirname "$0")/.."
  exec "$@"
fi
