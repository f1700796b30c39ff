#!/usr/bin/env bash
# Refuses an #include that points against the layers' arrows (../shared/CONVENTIONS.md, "Layers"):
#   base <- frame <- devices <- exporting <- engine <- ui <- tool,  frame <- processing <- render <- ui,
# and keeps GL, ImGui, V4L2 and libusb in the layers that own them. Prints each offending line as
# file:line: and exits 1. The build runs it before compiling anything (target check_layers); the include
# roots make the same mistake a compile error, this says which arrow it breaks.
# Usage: check-layers.sh [SOURCE_ROOT]
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}

ours='base|frame|devices|processing|exporting|engine|render|ui|tool'
gl='epoxy/|GLFW/|GL/|EGL/'
imgui='imgui|backends/imgui'
kernel='linux/videodev2|libusb'

# layer -> extended regex of the include paths it must not name
declare -A forbidden=(
    [base]="^(frame|devices|processing|exporting|engine|render|ui|tool)/|opencv2/|$gl|$imgui|$kernel"
    [frame]="^(devices|processing|exporting|engine|render|ui|tool)/|$gl|$imgui|$kernel"
    [devices]="^(processing|exporting|engine|render|ui|tool)/|$gl|$imgui"
    [processing]="^(devices|exporting|engine|render|ui|tool)/|$gl|$imgui|$kernel"
    [exporting]="^(engine|render|ui|tool)/|$gl|$imgui|$kernel"
    [engine]="^(render|ui|tool)/|$gl|$imgui|$kernel"
    [render]="^(devices|exporting|engine|ui|tool)/|$imgui|$kernel"
    # ui/ draws through ImGui's GLFW backend, so it may name GLFW's key codes; GL calls belong to render/.
    [ui]="^(tool|devices/uvc)/|epoxy/|GL/|EGL/|$kernel"
)

status=0
for layer in "${!forbidden[@]}"; do
    [ -d "$root/$layer" ] || continue
    while IFS= read -r hit; do
        file=${hit%%:*}
        rest=${hit#*:}
        line=${rest%%:*}
        text=${rest#*:}
        included=$(sed -E 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]([^>"]+)[>"].*/\1/' <<<"$text")
        if grep -Eq "${forbidden[$layer]}" <<<"$included"; then
            echo "${file#"$root"/}:$line: $layer/ must not include <$included>" >&2
            status=1
        fi
    done < <(grep -rnE '^[[:space:]]*#[[:space:]]*include' "$root/$layer" --include='*.h' --include='*.cpp' || true)
done
if [ "$status" -ne 0 ]; then
    echo "check-layers: includes against the layers' arrows (see ../shared/CONVENTIONS.md)" >&2
fi
exit "$status"
