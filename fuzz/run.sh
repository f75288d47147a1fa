#!/usr/bin/env bash
# Seeds the corpus of one target and runs it.
# Usage: fuzz/run.sh read_obj|read_ply|read_off|read_stl|read_scattered|parse_options|mesh_topology \
#        [seconds] [extra cargo-fuzz args...]
set -euo pipefail
target=$1
seconds=${2:-600}
shift $(( $# >= 2 ? 2 : 1 ))
cd "$(dirname "$0")/.."
corpus=fuzz/corpus/$target
mkdir -p "$corpus"
case $target in
read_scattered)
    # CSV data as `surfkit fit` reads it, shape points, and a small mesh (height field).
    printf 'u,v,x,y,z\n0,0,0,0,0\n1,0,1,0,0.5\n0,1,0,1,0.25\n1,1,1,1,1 # c\n' >"$corpus/data.csv"
    printf 'u,v\n0.5,0.5\n0.25;0.75\n' >"$corpus/points.csv"
    cp fixtures/meshes/catmark_torus.obj "$corpus/"
    ext=none ;;
parse_options)
    for s in 'genus=1,boundaries=2' 'genus=0,boundaries=0,components=3' '512M' '2.5GiB' \
        '0.2*math::sin(u - v)' 'if(u > 0.5, u^2, -v)' '1/(u-v)'; do
        printf '%s' "$s" >"$corpus/$(printf '%s' "$s" | md5sum | cut -c1-12)"
    done
    ext=none ;;
mesh_topology)
    ext=none ;;  # the fuzzer's own bytes are meshes
*)
    ext=${target#read_} ;;
esac
# Inputs that once crashed a target (kept as regressions) start every run.
[ -d "fuzz/regressions/$target" ] && cp fuzz/regressions/"$target"/* "$corpus"/
# Small real meshes (under 20 kB) plus the malformed ones: the fuzzer starts near both.
[ "$ext" = none ] || find fixtures/meshes fixtures/bad -name "*.$ext" -size -20k -exec cp {} "$corpus"/ \;
# fixtures/meshes has no small PLY and one small OFF: convert two small OBJ meshes
# (quads with UVs; objects) with surfkit itself, in every encoding it writes.
if [ "$ext" = ply ] || [ "$ext" = off ] || [ "$ext" = stl ]; then
    for m in catmark_torus joined_tetrahedra; do
        cargo run --quiet -- convert --keep-degenerate "fixtures/meshes/$m.obj" "$corpus/$m.$ext" >/dev/null
        if [ "$ext" = ply ] || [ "$ext" = stl ]; then
            cargo run --quiet -- convert --keep-degenerate --ascii "fixtures/meshes/$m.obj" "$corpus/${m}_ascii.$ext" >/dev/null
        fi
    done
fi
exec cargo +nightly fuzz run "$@" "$target" "$corpus" -- \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
