#!/usr/bin/env bash
# Compares two builds of the `lsubdiv` binary output by output, byte for byte: every shipped
# surface scheme on a sample of OpenSubdiv's shapes and the public models (positions, limit,
# texture coordinates, binary PLY), curves, reports, code, pictures. For a change that must not
# change any output (a refactoring): `tests/tools/same_outputs.sh OLD_BINARY NEW_BINARY`.
# Prints the number of outputs compared and each one that differs; exits 1 if any does.
set -uo pipefail
old=$1 new=$2
here=$(cd "$(dirname "$0")/../.." && pwd)
shared=$here/../shared
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
compared=0 succeeded=0 differ=0
# Runs `lsubdiv ARGS` with both binaries, OUT in ARGS naming the output file (in a folder of
# each binary's own); compares the files written, standard output and the exit status.
same() {
    local which bin
    for which in old new; do
        bin=${!which}
        rm -rf "${work:?}/$which" && mkdir "$work/$which"
        "$bin" "${@//OUT/$work/$which/o}" >"$work/$which.stdout" 2>/dev/null
        echo "status $?" >>"$work/$which.stdout"
    done
    compared=$((compared + 1))
    grep -qx "status 0" "$work/new.stdout" && succeeded=$((succeeded + 1))
    if ! cmp -s "$work/old.stdout" "$work/new.stdout" || ! diff -rq "$work/old" "$work/new" >/dev/null; then
        differ=$((differ + 1))
        echo "differs: lsubdiv $*"
    fi
}
schemes=$("$new" schemes)
meshes=()
for f in catmark_cube catmark_chaikin1 catmark_fvar_bound1 catmark_nonman_edges catmark_pole8 \
    catmark_single_crease catmark_torus_creases1 catmark_hole_test2 catmark_val2_interior; do
    [ -f "$shared/osd_shapes/$f.obj" ] && meshes+=("$shared/osd_shapes/$f.obj")
done
for f in cow.obj spot_control_mesh.obj suzanne.obj teapot.obj oloid256_quad.obj; do
    [ -f "$shared/models/$f" ] && meshes+=("$shared/models/$f")
done
[ ${#meshes[@]} -gt 0 ] || echo "note: ../shared absent: meshes compared from the built-in ones only"
for s in $schemes; do
    "$new" inspect "$s" --json >/dev/null 2>&1 || continue
    same inspect "$s" --json
    same graph "$s" --dot
    same codegen "$s" -o OUT
    same ev "$s" --valence 3..9 --json
    same plot "$s" -o OUT.svg
    for m in "${meshes[@]}"; do
        same subdivide "$s" "$m" --steps 2 -o OUT.obj
        same subdivide "$s" "$m" --steps 3 --limit -o OUT.obj
        same subdivide "$s" "$m" --steps 2 --uv smooth -o OUT.obj
        same subdivide "$s" "$m" --steps 2 --boundary edge-only --binary -o OUT.ply
    done
    same render cube --scheme "$s" --steps 3 --size 200x150 -o OUT.png
done
printf '0 0\n1 0\n1 1\n0 1\n0.5 2\n' >"$work/points.txt"
for s in $schemes; do
    same curve "$s" "$work/points.txt" --steps 4 --closed -o OUT
    same curve "$s" "$work/points.txt" --steps 3 --ends interpolate --limit -o OUT
done
echo "$compared runs compared ($succeeded of them succeeded, the others refused alike), $differ differ"
[ "$differ" = 0 ]
