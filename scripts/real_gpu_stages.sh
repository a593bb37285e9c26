#!/usr/bin/env bash
# Per-stage GPU times on a lent GPU (issue 16 item 6), for one or more
# builds side by side on the same machine: `trample simulate --backend gpu`
# (its profiling mode: timestamp queries, `summary.json`'s `stages_ms`) on
# the default scene, `scenes/herd.toml` and `scenes/herd_parked.toml`, for
# each binary named in BINS; then `trample bench --backend gpu` on the
# default scene and the herd with the first binary (not with BENCH=0).
#
# Here, once per build to compare: `bash scripts/real_gpu_bench.sh
# --prepare` (the loaders in .gl/, a stripped build in .carry/trample, and
# the `stage_times` and `record_time` examples where they were built);
# copy an older build to .carry/NAME to compare with it. Then, with the
# device tool, from the repo root:
#
#   run(command = "ROUNDS=2 BINS='trample trample_old' bash scripts/real_gpu_stages.sh",
#       carry = [".carry", ".gl"], timeout_s = 400)
#
# (ROUNDS=2: the builds once in order, once reversed; see below.) Writes
# into $OUT: log.txt and SCENE_BIN.json (each run's summary.json; NAME_r2
# for the second round), or, past seven of them (the tool brings back
# eight files), summaries.tar.gz holding them.
# QUICK=1 runs a few frames (to check the script on a software driver:
# WGPU_BACKEND=gl QUICK=1 HERD=scenes/herd_small.toml PARKED=... OUT=...).
set -u
BINS=${BINS:-trample}
DIR=${DIR:-.carry}
HERD=${HERD:-scenes/herd.toml}
PARKED=${PARKED:-scenes/herd_parked.toml}
# shellcheck source=scripts/device_setup.sh
. "$(dirname "$0")/device_setup.sh"
export WGPU_BACKEND=${WGPU_BACKEND:-vulkan}
nvidia-smi -L >>"$log" 2>&1

# run LIMIT_S NAME ARGS...: one trample command, logged.
run() {
    local limit=$1 name=$2
    shift 2
    echo "== $name: $* ($(date -u +%T))" >>"$log"
    timeout "$limit" "$@" >>"$log" 2>&1
    echo "== $name: exit $?" >>"$log"
}

# A build may travel gzipped (`$DIR/NAME.gz`, `gzip -k` here, the plain
# one moved out of DIR): with this repo's 12 MiB of tracked files, three
# stripped builds exceed the device tool's 64 MiB (session 44). It is
# unpacked into the scratch folder.
bin_path() {
    if [ ! -x "$DIR/$1" ] && [ -f "$DIR/$1.gz" ]; then
        [ -x "$work/$1" ] || { gunzip -c "$DIR/$1.gz" >"$work/$1" && chmod +x "$work/$1"; }
        echo "$work/$1"
    else
        echo "$DIR/$1"
    fi
}

# ROUNDS=2 runs the builds again in the reverse order (named NAME_r2):
# on an H200 one build run twice a minute apart gave the default scene's
# step as 1.6 and 2.5 ms (session 24), so compare builds within a round
# and across both orders, never one run against another's.
json=$work/json
mkdir -p "$json"
reversed=$(echo "$BINS" | tr ' ' '\n' | tac | tr '\n' ' ')
for round in $(seq 1 "${ROUNDS:-1}"); do
    order=$BINS
    suffix=
    if [ "$round" -gt 1 ]; then
        suffix=_r$round
        [ $((round % 2)) = 0 ] && order=$reversed
    fi
    for bin in $order; do
        t=$(bin_path "$bin")
        name=$bin$suffix
        run 40 "default_$name" "$t" simulate --backend gpu --precision 7 \
            --frames "$(frames 300 3)" --out "$work/default_$name"
        run 60 "herd_$name" "$t" simulate "$HERD" --backend gpu --frames "$(frames 100 2)" \
            --out "$work/herd_$name"
        run 60 "parked_$name" "$t" simulate "$PARKED" --backend gpu --frames "$(frames 100 2)" \
            --out "$work/parked_$name"
        # FAR=K: the herd with far objects taking turns (`--far-every K`).
        if [ -n "${FAR:-}" ]; then
            run 60 "herdfar_$name" "$t" simulate "$HERD" --backend gpu --far-every "$FAR" \
                --frames "$(frames 100 2)" --out "$work/herdfar_$name"
        fi
        for s in default herd parked herdfar; do
            f=$work/${s}_$name/summary.json
            [ -f "$f" ] && cp "$f" "$json/${s}_$name.json"
        done
    done
done
# The herd's stages timed both ways, where `--prepare` carried the
# `stage_times` example: timestamps (as above) and wall time (each stage
# submitted and waited for) — on NVIDIA (session 21) a timestamp lap with
# no work in it read 0.21 ms on the herd, so the two are compared.
if [ -x "$DIR/stage_times" ]; then
    for mode in timestamp wall; do
        echo "== stage_times $mode: $HERD ($(date -u +%T))" >>"$log"
        TRAMPLE_STAGE_TIMING=$mode timeout 60 "$DIR/stage_times" "$(frames 12 3)" "$HERD" \
            >"$work/stage_times_$mode.txt" 2>&1
        echo "== stage_times $mode: exit $?" >>"$log"
        grep -E "^adapter|^stage timing" "$work/stage_times_$mode.txt" >>"$log"
        tail -n 4 "$work/stage_times_$mode.txt" >>"$log"
    done
fi
first=${BINS%% *}
[ "${BENCH:-1}" = 0 ] || {
run 40 bench_default "$(bin_path "$first")" bench --backend gpu --precisions 3,7 \
    --frames "$(frames 2000 3)" --out "$work/bench_default"
run 60 bench_herd "$(bin_path "$first")" bench "$HERD" --backend gpu --precisions 7 \
    --frames "$(frames 300 2)" --out "$work/bench_herd"
}
grep -E "^== |step median|^ +gpu +[0-9]" "$log"
python3 - "$json" <<'EOF' || true
import json, pathlib, sys
for f in sorted(pathlib.Path(sys.argv[1]).glob("*.json")):
    d = json.load(open(f))
    st = d["stages_ms"]
    print(f"{f.stem:22} step {d['step_ms']['median']:8.3f}  stages {sum(st.values()):8.3f}  "
          + " ".join(f"{k} {v:.3f}" for k, v in sorted(st.items()) if v))
EOF
# The device tool brings back eight files: past seven summaries they go
# back as one archive.
if [ "$(ls "$json" | wc -l)" -le 7 ]; then
    cp "$json"/*.json "$OUT"/ 2>/dev/null || true
else
    tar czf "$OUT/summaries.tar.gz" -C "$json" .
fi
