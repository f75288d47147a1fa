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
