#!/usr/bin/env bash
# Peer comparison for lsubdiv: OpenSubdiv (C++, Debian's libosd-dev), and the Rust crates
# subdiv-kernels and opensubdiv-rs, against lsubdiv's uniform-binary scheme (= Catmull-Clark on
# all-valence-4 meshes), same meshes, same output size. See README.md beside this file.
#
#   bash bench/peers/run.sh
#
# Not part of CI or of the lsubdiv workspace: every crate here is a standalone workspace built
# into its own target dir. A peer that cannot be installed or built is reported and skipped.
#
# Environment (all optional):
#   PEERS_TARGET  cargo target dir root          (default /tmp/peers-target)
#   PEERS_WORK    meshes, binaries, dumps, logs  (default /tmp/peers-work)
#   PEERS_ROUNDS  interleaved rounds             (default 3)
#   PEERS_RUNS    timed runs per invocation      (default 7; median taken; min 7 advised)
#   PEERS_SKIP    space-separated peers to skip: osd subdiv-kernels opensubdiv-rs

set -u -o pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
TARGET=${PEERS_TARGET:-/tmp/peers-target}
WORK=${PEERS_WORK:-/tmp/peers-work}
ROUNDS=${PEERS_ROUNDS:-3}
RUNS=${PEERS_RUNS:-7}
SKIP=" ${PEERS_SKIP:-} "
LOGS="$WORK/logs"
RESULTS="$WORK/results.txt"
mkdir -p "$WORK" "$LOGS"
: >"$RESULTS"
START=$(date +%s)

say() { printf '%s\n' "$*"; }
skipped() { [[ "$SKIP" == *" $1 "* ]]; }

SUDO=
if [ "$(id -u)" != 0 ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo -n"; fi
fi

APT_UPDATED=0
apt_install() { # apt_install PACKAGE... ; returns non-zero on failure
    if ! command -v apt-get >/dev/null 2>&1; then
        say "  (no apt-get on this machine)"
        return 1
    fi
    if [ "$APT_UPDATED" = 0 ]; then
        $SUDO apt-get update >"$LOGS/apt-update.log" 2>&1 || true
        APT_UPDATED=1
    fi
    $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y "$@" \
        >"$LOGS/apt-install.log" 2>&1
}

# ---------------------------------------------------------------------------------------------
say "## lsubdiv peer comparison"
say
say "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
say "rustc: $(rustc --version 2>/dev/null || echo missing)"
say "load average at start: $(cut -d" " -f1-3 /proc/loadavg) (other processes on the machine add noise)"

# --- lsubdiv harness (required) ---------------------------------------------------------------
say
say "### build"
if [ ! -f "$HERE/rust/Cargo.lock" ] && [ -f "$ROOT/Cargo.lock" ]; then
    # Start from the main project's pinned versions (cargo adds what is missing).
    cp "$ROOT/Cargo.lock" "$HERE/rust/Cargo.lock"
fi
if (cd "$HERE/rust" && CARGO_TARGET_DIR="$TARGET/lsubdiv" cargo build --release) \
    >"$LOGS/build-lsubdiv.log" 2>&1; then
    LS="$TARGET/lsubdiv/release/lsubdiv-peers"
    say "- lsubdiv harness: built"
else
    say "- lsubdiv harness: FAILED to build (see $LOGS/build-lsubdiv.log); nothing to compare against"
    tail -20 "$LOGS/build-lsubdiv.log"
    exit 1
fi

PEERS=()   # names, in run order

# --- OpenSubdiv C++ -------------------------------------------------------------------------
OSD_BIN="$WORK/osd_bench"
if skipped osd; then
    say "- opensubdiv-c++: skipped (PEERS_SKIP)"
else
    if ! command -v g++ >/dev/null 2>&1; then
        say "  installing g++ …"
        apt_install g++ || say "  g++ install failed (see $LOGS/apt-install.log)"
    fi
    if [ ! -f /usr/include/opensubdiv/far/primvarRefiner.h ]; then
        say "  installing libosd-dev …"
        apt_install libosd-dev || say "  libosd-dev install failed (see $LOGS/apt-install.log)"
    fi
    if ! command -v g++ >/dev/null 2>&1; then
        say "- opensubdiv-c++: NOT BUILT: no g++"
    elif [ ! -f /usr/include/opensubdiv/far/primvarRefiner.h ]; then
        say "- opensubdiv-c++: NOT BUILT: OpenSubdiv headers missing (libosd-dev not installed)"
    elif g++ -O3 -DNDEBUG -std=c++14 -o "$OSD_BIN" "$HERE/osd_bench.cpp" -losdCPU \
        >"$LOGS/build-osd.log" 2>&1; then
        OSD_VER=$(dpkg-query -W -f='${Version}' libosd-dev 2>/dev/null || echo '?')
        say "- opensubdiv-c++: built (libosd-dev $OSD_VER, $(g++ --version | head -1), -O3)"
        PEERS+=(opensubdiv-c++)
    else
        say "- opensubdiv-c++: NOT BUILT: compile failed (see $LOGS/build-osd.log)"
        tail -5 "$LOGS/build-osd.log"
    fi
fi

# --- Rust peer crates -----------------------------------------------------------------------
declare -A BIN
BIN[opensubdiv-c++]="$OSD_BIN"
for crate in subdiv-kernels opensubdiv-rs; do
    if skipped "$crate"; then
        say "- $crate: skipped (PEERS_SKIP)"
        continue
    fi
    dir="$HERE/rust/peers/$crate"
    log="$LOGS/build-$crate.log"
    if (cd "$dir" && CARGO_TARGET_DIR="$TARGET/$crate" cargo build --release) >"$log" 2>&1; then
        ver=$(grep -A1 "^name = \"$crate\"" "$dir/Cargo.lock" | sed -n 's/^version = "\(.*\)"/\1/p')
        say "- $crate: built (crate version $ver)"
        BIN[$crate]="$TARGET/$crate/release/peer-$crate"
        PEERS+=("$crate")
    elif grep -qE "no matching package|failed to select a version|could not find" "$log"; then
        say "- $crate: NOT BUILT: crate not found in the registry (see $log)"
    else
        say "- $crate: NOT BUILT: build failed (see $log)"
        grep -m3 -E "^error" "$log" | sed 's/^/    /'
    fi
done

# --- meshes ---------------------------------------------------------------------------------
say
say "### meshes (written by lsubdiv::bench::mesh + to_obj; levels as \`lsubdiv bench\` picks them for ~4.2M output vertices)"
MESHES=()
declare -A OBJ LEVELS
while read -r tag name path levels outv; do
    [ "$tag" = MESH ] || continue
    MESHES+=("$name")
    OBJ[$name]=$path
    LEVELS[$name]=$levels
    say "- $name: $path, $levels levels, $outv output vertices"
done < <("$LS" meshes --dir "$WORK/meshes")
if [ ${#MESHES[@]} = 0 ]; then
    say "could not write the meshes"
    exit 1
fi

# --- timing, interleaved ---------------------------------------------------------------------
run_one() { # run_one IMPL MESH ROUND [--dump FILE]; appends RESULT or FAILED lines
    local imp=$1 mesh=$2 round=$3
    shift 3
    local log="$LOGS/run-$imp-$mesh-$round.log" cmd
    if [ "$imp" = lsubdiv ]; then
        cmd=("$LS" bench)
    else
        cmd=("${BIN[$imp]}")
    fi
    timeout 300 "${cmd[@]}" --obj "${OBJ[$mesh]}" --name "$mesh" --levels "${LEVELS[$mesh]}" \
        --runs "$RUNS" "$@" >"$log" 2>&1
    local rc=$?
    if [ $rc = 0 ] && grep -q "^RESULT " "$log"; then
        grep '^RESULT ' "$log" | tee -a "$RESULTS" | sed "s/^/  [round $round] /"
    else
        local why
        why=$(grep -m1 -iE "error|panick|killed" "$log" | tr ' =' '__' | cut -c1-80)
        echo "FAILED impl=$imp mesh=$mesh reason=${why:-exit_status_$rc}" | tee -a "$RESULTS"
    fi
}

say
say "### runs ($ROUNDS rounds; in each, per mesh: lsubdiv, peer, lsubdiv, peer, …; each invocation = 1 warm-up + median of $RUNS)"
for ((r = 1; r <= ROUNDS; r++)); do
    for mesh in "${MESHES[@]}"; do
        for peer in "${PEERS[@]}"; do
            # The creased torus only where its crease tags are read (OpenSubdiv's harness).
            [ "$mesh" = creased ] && [ "$peer" != opensubdiv-c++ ] && continue
            dump=()
            # Round 1 on the torus, the open grid and the creased torus also writes the refined
            # meshes for the accuracy check (after timing, untimed).
            checked() { [ "$r" = 1 ] && [[ " torus grid creased " == *" $mesh "* ]]; }
            checked && dump=(--dump "$WORK/$mesh-lsubdiv.bin")
            run_one lsubdiv "$mesh" "$r" "${dump[@]}"
            dump=()
            checked && dump=(--dump "$WORK/$mesh-$peer.bin")
            run_one "$peer" "$mesh" "$r" "${dump[@]}"
        done
        [ ${#PEERS[@]} = 0 ] && run_one lsubdiv "$mesh" "$r"
    done
done

# --- accuracy --------------------------------------------------------------------------------
say
say "### accuracy (torus ${LEVELS[torus]:-3} levels, open grid ${LEVELS[grid]:-8}, creased torus ${LEVELS[creased]:-3}; vertices matched by position, tolerance 1e-9; required <= 1e-12 vs OpenSubdiv)"
ACC="$WORK/accuracy.txt"
: >"$ACC"
[ ${#PEERS[@]} = 0 ] && say "(no peer was built: nothing to compare)"
for mesh in torus grid creased; do
    for peer in "${PEERS[@]}"; do
        [ "$mesh" = creased ] && [ "$peer" != opensubdiv-c++ ] && continue
        if [ -f "$WORK/$mesh-lsubdiv.bin" ] && [ -f "$WORK/$mesh-$peer.bin" ]; then
            "$LS" compare --a "$WORK/$mesh-lsubdiv.bin" --b "$WORK/$mesh-$peer.bin" \
                --label "$mesh:lsubdiv-vs-$peer" 2>&1 | tee -a "$ACC"
        else
            say "$mesh:lsubdiv-vs-$peer: no dump (run failed)" | tee -a "$ACC"
        fi
        rm -f "$WORK/$mesh-$peer.bin"
    done
    rm -f "$WORK/$mesh-lsubdiv.bin"
done
if [[ " ${PEERS[*]} " == *" opensubdiv-c++ "* ]]; then
    say
    say "informational, meshes with extraordinary vertices (3 levels, tolerance 1e-2): lsubdiv's"
    say "uniform-binary scheme uses its own eigen-tuned EV rule, not Catmull-Clark's, so these differ"
    for mesh in cube star; do
        [ -n "${OBJ[$mesh]:-}" ] || continue
        "$LS" bench --obj "${OBJ[$mesh]}" --name "$mesh" --levels 3 --runs 0 \
            --dump "$WORK/$mesh-lsubdiv.bin" >/dev/null 2>&1 &&
            "$OSD_BIN" --obj "${OBJ[$mesh]}" --name "$mesh" --levels 3 --runs 1 \
                --dump "$WORK/$mesh-osd.bin" >/dev/null 2>&1 &&
            "$LS" compare --a "$WORK/$mesh-lsubdiv.bin" --b "$WORK/$mesh-osd.bin" --tol 1e-2 \
                --label "$mesh(3-levels):lsubdiv-vs-opensubdiv-c++" 2>&1 | tee -a "$ACC"
        rm -f "$WORK/$mesh-lsubdiv.bin" "$WORK/$mesh-osd.bin"
    done
fi

# --- table -----------------------------------------------------------------------------------
say
say "### results (M output vertices/s, f64 positions, 1 thread; ratio > 1 means lsubdiv is faster)"
say
"$LS" table --results "$RESULTS"
say
say "load average at end: $(cut -d" " -f1-3 /proc/loadavg)"
say "total time: $(($(date +%s) - START)) s; raw lines in $RESULTS, logs in $LOGS"
