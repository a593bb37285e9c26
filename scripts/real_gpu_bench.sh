#!/usr/bin/env bash
# The measurements that need a real GPU (issue 16 item 6; DESIGN §10's GPU
# targets), as one short run for a machine lent by the `device` tool:
#
#   1. the default scene (the paper's field, one ball), simulation alone,
#      GPU and CPU paths, precisions 3 and 7;
#   2. the same, simulation + a 1920x1080 frame on the GPU;
#   3. scenes/herd.toml (128 objects over 16.8 M blades), simulation alone,
#      both paths;
#   4. the herd, simulation + a 1920x1080 frame (2 and 4: each frame read
#      back, then drawn and waited for without the read-back);
#   5. the herd's step against the object count (1 … 128), GPU path.
#
# Here (a checkout with a release build: `cargo build --release -p
# trample-cli`), once:
#
#   bash scripts/real_gpu_bench.sh --prepare
#
# puts a stripped `trample` in .carry/ and the Vulkan/GL loaders in .gl/
# (both ignored by git). Then, with the device tool, from the repo root:
#
#   run(command = "bash scripts/real_gpu_bench.sh",
#       carry = [".carry", ".gl"], timeout_s = 600)
#
# It writes into $OUT (at most 8 files, the tool's limit): adapter.txt,
# log.txt, default.json, default_1080p.json, herd.json, herd_1080p.json,
# objects.json, objects.png (and herd_farK.json with FAR=K: then OBJECTS=0
# or an archive, to stay within eight). Each step has its own time limit, so one that
# hangs costs only its share (665 s in all, more with the fallbacks: keep
# timeout_s above what the run needs, not above that sum). On an H200 (16
# cores) the whole run took 180 s before the `--no-readback` steps were
# added (2026-11-26); QUICK=1 on lavapipe takes about 2.5 minutes on 2
# cores. Record the figures in BENCHMARKS.md with the adapter's name.
#
# To check the script without a GPU (software driver, small scene, a few
# frames): WGPU_BACKEND=gl QUICK=1 HERD=scenes/herd_small.toml
# OUT=/tmp/real_gpu TRAMPLE=target/release/trample bash scripts/real_gpu_bench.sh
# (SCENE=FILE replaces the default scene too: the CLI's test
# `the_real_gpu_script_runs_every_step` runs it that way on small scenes).
set -u

# The first source file newer than the build $1, if any: a build older
# than the sources carries the wrong code (`cargo build -p trample-cli -p
# trample-gpu --example X` builds the examples only, not the CLI; session
# 24 measured a stale build so).
newer_source() {
    find crates -newer "$1" -type f \( -name '*.rs' -o -name '*.wgsl' -o -name Cargo.toml \) | head -n 1
}

if [ "${1:-}" = "--prepare" ]; then
    set -e
    bin=target/release/trample
    [ -x "$bin" ] || { echo "no $bin: run cargo build --release -p trample-cli first" >&2; exit 1; }
    newer=$(newer_source "$bin")
    if [ -n "$newer" ]; then
        echo "$bin is older than $newer: run cargo build --release -p trample-cli (on its own) first" >&2
        exit 1
    fi
    mkdir -p .carry .gl
    strip -o .carry/trample "$bin"
    # The GPU examples, where built (`cargo build --release -p trample-gpu
    # --example stage_times --example record_time`): real_gpu_stages.sh
    # runs stage_times; record_time is run by hand.
    for e in stage_times record_time; do
        if [ -x "target/release/examples/$e" ]; then
            if [ -n "$(newer_source "target/release/examples/$e")" ]; then
                echo "target/release/examples/$e is older than the sources: not carried" >&2
                continue
            fi
            strip -o ".carry/$e" "target/release/examples/$e"
        fi
    done
    o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
    mkdir -p /tmp/amd64/partial
    # shellcheck disable=SC2086
    apt-get $o update -qq
    # shellcheck disable=SC2086
    (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
    du -sh .carry .gl
    exit 0
fi

TRAMPLE=${TRAMPLE:-.carry/trample}
HERD=${HERD:-scenes/herd.toml}
# The paper's field: the embedded default scene unless SCENE names a file.
SCENE=${SCENE:-}
# shellcheck source=scripts/device_setup.sh
. "$(dirname "$0")/device_setup.sh"

# The backend: WGPU_BACKEND if set, else Vulkan, else GL (EGL) where a
# two-frame GPU run of the default scene fails on Vulkan.
probe() {
    # shellcheck disable=SC2086
    WGPU_BACKEND=$1 timeout 30 "$TRAMPLE" bench $SCENE --backend gpu --precisions 3 \
        --frames 2 --out "$work/probe_$1" >>"$log" 2>&1
}
if [ -z "${WGPU_BACKEND:-}" ]; then
    for b in vulkan gl; do
        echo "== probe: WGPU_BACKEND=$b ($(date -u +%T))" >>"$log"
        if probe $b; then
            export WGPU_BACKEND=$b
            break
        fi
    done
    export WGPU_BACKEND=${WGPU_BACKEND:-vulkan}
fi

{
    date -u
    uname -a
    nproc
    nvidia-smi -L 2>/dev/null || echo "no nvidia-smi"
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv 2>/dev/null
    echo "WGPU_BACKEND=$WGPU_BACKEND"
    "$TRAMPLE" --version
} >"$OUT/adapter.txt" 2>&1

# step NAME LIMIT_S ARGS...: one `trample bench` run into $work/NAME,
# its output appended to the log, its JSON copied to $OUT/NAME.json.
step() {
    local name=$1 limit=$2
    shift 2
    local dir=$work/$name
    echo "== $name: trample bench $* ($(date -u +%T))" >>"$log"
    local start=$SECONDS
    timeout "$limit" "$TRAMPLE" bench "$@" --out "$dir" >>"$log" 2>&1
    local rc=$?
    echo "== $name: exit $rc after $((SECONDS - start)) s" >>"$log"
    for f in "$dir"/bench.json "$dir"/objects.json; do
        [ -f "$f" ] && cp "$f" "$OUT/$name.json"
    done
    return 0
}

# shellcheck disable=SC2086 # an empty SCENE is no argument
step default 45 $SCENE --backend both --precisions 3,7 --frames "$(frames 2000 3)"
# shellcheck disable=SC2086
step default_1080p 45 $SCENE --backend gpu --render --size 1920x1080 --precisions 7 \
    --frames "$(frames 1000 2)"
step herd 150 "$HERD" --backend both --precisions 7 --frames "$(frames 300 2)"
# Where the adapter cannot hold the herd (its storage binding limit), the
# log says so and the herd on a 32 x 32-patch field stands in for it.
# The full herd's CPU figures then go to the log alone.
if [ ! -f "$OUT/herd.json" ] && [ -f scenes/herd_small.toml ]; then
    echo "== herd: no result on the GPU; its CPU path alone, then herd_small.toml" >>"$log"
    step herd_cpu 90 "$HERD" --backend cpu --precisions 7 --frames "$(frames 300 2)"
    rm -f "$OUT/herd_cpu.json"
    HERD=scenes/herd_small.toml
    step herd 90 "$HERD" --backend both --precisions 7 --frames "$(frames 300 2)"
fi
step herd_1080p 90 "$HERD" --backend gpu --render --size 1920x1080 --precisions 7 \
    --frames "$(frames 200 2)"
# FAR=K: the herd again with far objects taking turns (`--far-every K`,
# issue 16's CPU budget is measured at K = 16), both paths: herd_farK.json.
if [ -n "${FAR:-}" ]; then
    step "herd_far$FAR" 150 "$HERD" --backend both --precisions 7 --frames "$(frames 300 2)" \
        --far-every "$FAR"
fi
# The frames drawn and waited for, not read back (what an application that
# presents them pays): in the log only (the tool's eight files).
# shellcheck disable=SC2086
step default_1080p_present 45 $SCENE --backend gpu --render --no-readback --size 1920x1080 \
    --precisions 7 --frames "$(frames 1000 2)"
step herd_1080p_present 90 "$HERD" --backend gpu --render --no-readback --size 1920x1080 \
    --precisions 7 --frames "$(frames 200 2)"
rm -f "$OUT/default_1080p_present.json" "$OUT/herd_1080p_present.json"
# OBJECTS=0 leaves out the objects series (its 170 s; measured in
# sessions 16 and 21) when the device time is short.
if [ "${OBJECTS:-1}" != 0 ]; then
    step objects 170 "$HERD" --objects --backend gpu --frames "$(frames 100 2)"
    [ -f "$work/objects/objects.png" ] && cp "$work/objects/objects.png" "$OUT/"
fi
grep -E "^== |^ +(cpu|gpu) +[0-9]|^ +[0-9]+ +[0-9]+x[0-9]+|^Simulation \+ rendering|^trample bench --objects" "$log" || true
ls -la "$OUT"
