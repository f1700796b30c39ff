#!/usr/bin/env bash
# Builds the .deb with CPack, installs it with apt into a fresh Debian 12 root that mmdebstrap makes from
# Debian's mirror (a plain chroot: no container), and runs `depthcloud --headless --frames 5` inside it, on
# Mesa's llvmpipe through EGL. So the package's Depends, derived by dpkg-shlibdeps, must be all it needs.
#
# Usage: DC_PACKAGE_TEST=1 deb_install_test.sh BUILD_DIR. Opt-in: it takes about ten minutes on two busy
# cores (cpack, then apt installing some 400 packages into the root), far beyond what the CI run can spare,
# so without DC_PACKAGE_TEST=1 it exits 77 (skipped). Needs root for chroot and the mounts mmdebstrap makes (CI runs as
# root); exits 77 (skipped) otherwise. Downloaded packages are kept in BUILD_DIR/package-test/apt-cache, so
# only the first run downloads. DC_DEBIAN_MIRROR overrides the mirror (default http://deb.debian.org).
set -euo pipefail

build=$(realpath "$1")
work=$build/package-test
cache=$work/apt-cache
mirror=${DC_DEBIAN_MIRROR:-http://deb.debian.org}

if [ "${DC_PACKAGE_TEST:-0}" != 1 ]; then
    echo "deb_install_test: opt-in (about ten minutes); run with DC_PACKAGE_TEST=1; skipped" >&2
    exit 77
fi
if [ "$(id -u)" -ne 0 ]; then
    echo "deb_install_test: needs root (chroot, mounts); skipped" >&2
    exit 77
fi
fail() {
    echo "deb_install_test: $*" >&2
    exit 1
}
for tool in cpack mmdebstrap desktop-file-validate; do
    command -v "$tool" >/dev/null || fail "$tool is missing (scripts/setup.sh installs it)"
done

rm -rf "$work/deb" "$work/snapshots" "$work/tmp"
mkdir -p "$work/deb" "$cache" "$work/tmp"
start=$(date +%s)
cpack --config "$build/CPackConfig.cmake" -G DEB -B "$work/deb" >"$work/cpack.log" 2>&1 ||
    fail "cpack failed: $(cat "$work/cpack.log")"
deb=$(ls "$work"/deb/depthcloud_*.deb)
echo "deb_install_test: $(basename "$deb"), $(stat -c %s "$deb") bytes, built in $(($(date +%s) - start)) s"
dpkg-deb --field "$deb" Depends
dpkg-deb --extract "$deb" "$work/deb/contents"
desktop-file-validate "$work/deb/contents/usr/share/applications/depthcloud.desktop"

# The root lives in the build directory, not in a small /tmp. The essential packages stay in the root's apt
# cache (essential/unlink skipped) so that sync-out keeps them too; dpkg need not fsync a root it discards.
export TMPDIR=$work/tmp
start=$(date +%s)
mmdebstrap --mode=root --variant=apt --format=null \
    --include="$deb" --hook-dir=/usr/share/mmdebstrap/hooks/file-mirror-automount \
    --skip=essential/unlink --dpkgopt=force-unsafe-io --aptopt='Acquire::Languages "none"' \
    --setup-hook='mkdir -p "$1"/var/cache/apt/archives/' \
    --setup-hook="sync-in $cache /var/cache/apt/archives/" \
    --customize-hook="sync-out /var/cache/apt/archives $cache" \
    --customize-hook='chroot "$1" depthcloud --version' \
    --customize-hook='chroot "$1" depthcloud --headless --frames 5 --out /tmp/snapshots' \
    --customize-hook="copy-out /tmp/snapshots $work" \
    bookworm /dev/null \
    "deb $mirror/debian bookworm main" \
    "deb $mirror/debian bookworm-updates main" \
    "deb $mirror/debian-security bookworm-security main"
echo "deb_install_test: installed and ran in a fresh root in $(($(date +%s) - start)) s"

for png in cloud depth confidence camera; do
    [ -s "$work/snapshots/$png.png" ] || fail "no $png.png from the installed binary"
done
grep -q '"frames": *5' "$work/snapshots/summary.json" || fail "summary.json does not count 5 frames"
rm -rf "$work/tmp"
echo "deb_install_test: passed"
