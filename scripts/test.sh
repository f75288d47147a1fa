#!/usr/bin/env bash
# Runs every test suite of surfkit (README's test command calls this through scripts/setup.sh):
# the Rust workspace (unit, integration and the C++ examples built against an install), then
# any further suites a later part of the project adds below.
set -euo pipefail
cd "$(dirname "$0")/.."
# `cargo test` builds no cdylib/staticlib for a crate that has no rlib (capi), yet the C++ tests
# link libsurfkit.so and libsurfkit.a: build the whole workspace first.
cargo build --release --workspace
cargo test --release --workspace
# The Python package (python/: PyO3 + maturin) built into .venv, then its tests (which compare
# with the CLI built above, pymeshlab and trimesh) and ruff.
venv="$(dirname "$(dirname "${SURFKIT_PYTHON:-$PWD/.venv/bin/python}")")"
VIRTUAL_ENV="$venv" CARGO_TARGET_DIR="$PWD/target/python" \
  "$venv/bin/maturin" develop --release --quiet -m python/Cargo.toml
"$venv/bin/ruff" check python tests/browser
"$venv/bin/ruff" format --check python tests/browser
"$venv/bin/python" -m pytest -q python/tests
# The HTML reports in headless Chromium (network off), driven by WebDriver; screenshots
# are left in target/test-artifacts/browser.
"$venv/bin/python" -m pytest -q tests/browser
