#!/usr/bin/env bash
# Seeds the corpus of one target from fixtures/ and runs it.
# Usage: fuzz/run.sh read_obj|read_ply|read_off [seconds] [extra cargo-fuzz args...]
set -euo pipefail
target=$1
seconds=${2:-600}
shift $(( $# >= 2 ? 2 : 1 ))
cd "$(dirname "$0")/.."
ext=${target#read_}
corpus=fuzz/corpus/$target
mkdir -p "$corpus"
# Small real meshes (under 20 kB) plus the malformed ones: the fuzzer starts near both.
find fixtures/meshes fixtures/bad -name "*.$ext" -size -20k -exec cp {} "$corpus"/ \;
# fixtures/meshes has no small PLY and one small OFF: convert two small OBJ meshes
# (quads with UVs; objects) with surfkit itself, in every encoding it writes.
if [ "$ext" != obj ]; then
    for m in catmark_torus joined_tetrahedra; do
        cargo run --quiet -- convert --keep-degenerate "fixtures/meshes/$m.obj" "$corpus/$m.$ext" >/dev/null
        if [ "$ext" = ply ]; then
            cargo run --quiet -- convert --keep-degenerate --ascii "fixtures/meshes/$m.obj" "$corpus/${m}_ascii.ply" >/dev/null
        fi
    done
fi
exec cargo +nightly fuzz run "$@" "$target" "$corpus" -- \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
