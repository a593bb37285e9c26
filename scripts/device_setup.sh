# Sourced by the scripts run on a lent GPU (`real_gpu_bench.sh`,
# `real_gpu_stages.sh`): the results folder and its log, a scratch folder
# removed on exit, the frame counts of the QUICK check, and the loaders the
# device machine lacks (see the device tool's README: the .deb files that
# `real_gpu_bench.sh --prepare` puts in .gl/).
#
# Sets OUT (required), QUICK, log, work; defines frames REAL QUICK.

OUT=${OUT:?set OUT to the folder for the results}
QUICK=${QUICK:-0}
log="$OUT/log.txt"
mkdir -p "$OUT"
# Each step's own output folder (charts and the like stay here: the tool
# brings back eight files at most).
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
: >"$log"

# Frames per step: the real run, or a handful to check a script.
frames() { if [ "$QUICK" = 1 ]; then echo "$2"; else echo "$1"; fi; }

if ls .gl/*.deb >/dev/null 2>&1; then
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
fi
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
egl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$icd" ] && export VK_DRIVER_FILES="$icd"
[ -f "$egl" ] && export __EGL_VENDOR_LIBRARY_FILENAMES="$egl"
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}
