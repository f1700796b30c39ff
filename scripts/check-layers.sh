#!/usr/bin/env bash
# Refuses an #include that points against the layers' arrows (../shared/CONVENTIONS.md, "Layers"):
#   base <- frame <- devices <- exporting <- engine <- ui <- tool,  frame <- processing <- render <- ui,
# and keeps GL, ImGui, V4L2, libusb and ROS in the layers that own them. Prints each offending line as
# file:line: and exits 1. The build runs it before compiling anything (target check_layers); the include
# roots make the same mistake a compile error, this says which arrow it breaks.
# Usage: check-layers.sh [SOURCE_ROOT]
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}

ours='base|frame|devices|processing|exporting|engine|render|ui|tool'
gl='epoxy/|GLFW/|GL/|EGL/'
imgui='imgui|backends/imgui'
kernel='linux/videodev2|libusb'
# ROS 1 headers (devices/ros only: they are C++17, see devices/ros/ros_messages.h).
ros='^(rosbag|ros|sensor_msgs|std_msgs|geometry_msgs)/'

# layer -> extended regex of the include paths it must not name
declare -A forbidden=(
    [base]="^(frame|devices|processing|exporting|engine|render|ui|tool)/|opencv2/|$gl|$imgui|$kernel|$ros"
    [frame]="^(devices|processing|exporting|engine|render|ui|tool)/|$gl|$imgui|$kernel|$ros"
    [devices]="^(processing|exporting|engine|render|ui|tool)/|$gl|$imgui"
    [processing]="^(devices|exporting|engine|render|ui|tool)/|$gl|$imgui|$kernel|$ros"
    [exporting]="^(engine|render|ui|tool)/|$gl|$imgui|$kernel|$ros"
    [engine]="^(render|ui|tool)/|$gl|$imgui|$kernel|$ros"
    [render]="^(devices|exporting|engine|ui|tool)/|$imgui|$kernel|$ros"
    # ui/ draws through ImGui's GLFW backend, so it may name GLFW's key codes; GL calls belong to render/.
    [ui]="^(tool|devices/uvc)/|epoxy/|GL/|EGL/|$kernel|$ros"
)

# One pass over every include line of every layer: "file:line:text" in, one message per violation out.
layers=()
for layer in "${!forbidden[@]}"; do
    [ -d "$root/$layer" ] && layers+=("$layer")
done
[ ${#layers[@]} -eq 0 ] && exit 0
rules=$(for layer in "${layers[@]}"; do printf '%s\t%s\n' "$layer" "${forbidden[$layer]}"; done)
violations=$(cd "$root" && grep -rnE '^[[:space:]]*#[[:space:]]*include' "${layers[@]}" \
    --include='*.h' --include='*.cpp' | awk -v rules="$rules" '
    BEGIN {
        n = split(rules, lines, "\n")
        for (i = 1; i <= n; ++i) { split(lines[i], kv, "\t"); rule[kv[1]] = kv[2] }
    }
    {
        file = $0; sub(/:.*/, "", file)
        rest = substr($0, length(file) + 2); line = rest; sub(/:.*/, "", line)
        text = substr(rest, length(line) + 2)
        layer = file; sub(/\/.*/, "", layer)
        included = text
        sub(/^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]/, "", included)
        sub(/[>"].*$/, "", included)
        if (included ~ rule[layer])
            printf "%s:%s: %s/ must not include <%s>\n", file, line, layer, included
    }')
if [ -n "$violations" ]; then
    printf '%s\n' "$violations" >&2
    echo "check-layers: includes against the layers' arrows (see ../shared/CONVENTIONS.md)" >&2
    exit 1
fi
