#!/usr/bin/env bash
# Installs, with apt-get, exactly the Debian 12 packages depthcloud needs that this machine lacks, then the
# node packages of the MCAP tests' writer (tests/mcap/writer, pinned by its package-lock.json).
# Idempotent: a second run installs nothing, and needs no network. Must run as root (or with sudo available).
set -euo pipefail

packages=(
    build-essential cmake pkg-config git
    libglfw3-dev libx11-dev libglm-dev libimgui-dev libepoxy-dev
    libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 libglx-mesa0
    libopencv-dev libopencv-contrib-dev libusb-1.0-0-dev libv4l-dev
    libgtest-dev libgmock-dev libbenchmark-dev
    libcli11-dev nlohmann-json3-dev libyaml-cpp-dev
    libzstd-dev liblz4-dev libxxhash-dev libsqlite3-dev libturbojpeg0-dev libpng-dev libudev-dev clang libclang-rt-14-dev
    xvfb xauth xdotool x11-apps openbox wmctrl python3-open3d
    qemu-system-x86 busybox-static cpio kmod v4l-utils xz-utils patch
    librosbag-storage-dev libsensor-msgs-dev libgeometry-msgs-dev libstd-msgs-dev
    cyclonedds-dev cyclonedds-tools libfastrtps-dev libfastcdr-dev
    python3-rosbag python3-roslz4 python3-sensor-msgs python3-geometry-msgs python3-std-msgs
    libroscpp-dev libtf2-dev libtf2-msgs-dev python3-roslaunch python3-rosmaster rosout python3-rospy
    python3-numpy python3-tf2-msgs nodejs
    help2man mmdebstrap debian-archive-keyring desktop-file-utils
)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done

# Debian's nodejs comes without npm; NodeSource's includes it (and conflicts with Debian's npm).
command -v npm >/dev/null || missing+=(npm)

# The writer's packages, again only when its lock file changed since they were installed.
install_node_packages() {
    local dir
    dir="$(dirname "$0")/../tests/mcap/writer"
    if [ "$dir/node_modules/.package-lock.json" -nt "$dir/package-lock.json" ]; then
        echo "setup: node packages of tests/mcap/writer already installed"
        return
    fi
    echo "setup: installing the node packages of tests/mcap/writer"
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
}

if [ ${#missing[@]} -eq 0 ]; then
    echo "setup: all ${#packages[@]} packages already installed"
    install_node_packages
    exit 0
fi

echo "setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
    sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
install_node_packages
echo "setup: done"
