#!/bin/bash
# build-initramfs.sh - the test VM of the kernel tier: Debian's own kernel (the one linux-image-amd64
# depends on) with a busybox initramfs that sets up a real V4L2/USB stack: a UVC gadget on an ISO-capable
# dummy_hcd (host side: uvcvideo + libusb), v4l2loopback patched for 'Z16 ', and vivid. Our own binaries
# are not copied in: the guest mounts the host's root read-only over virtio-9p and runs them in a chroot,
# with the host's libraries (Mesa included). Adapted from ../shared/vmkit.
#
# Needs only Debian packages: qemu-system-x86 busybox-static cpio kmod xz-utils patch gcc make libc6-dev.
# The kernel, its headers, linux-source (for dummy_hcd.c), v4l2loopback-dkms and udev (for libusb hotplug:
# libusb learns of hotplug through udevd) are fetched with `apt-get download` and extracted with
# `dpkg -x` into $WORK; nothing is installed on the host.
#
# Output: $OUT/vmlinuz, $OUT/initrd.img. Env: WORK (scratch and download cache), OUT, KVER.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=${WORK:?set WORK to a scratch directory}
OUT=${OUT:?set OUT to the output directory}
SRC=$HERE/src
mkdir -p "$WORK/debs" "$OUT"
t() { echo "[$(date +%T)] $*"; }

# a fresh machine may have no package lists yet (apt-get download needs them)
if ! apt-cache show linux-image-amd64 >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then apt-get update -qq; fi
if [ -z "${KVER:-}" ]; then
	KVER=$(apt-cache depends linux-image-amd64 | sed -n 's/.*Depends: linux-image-\(.*\)$/\1/p' | head -1)
fi
[ -n "$KVER" ] || { echo "cannot determine kernel version (apt-get update?)"; exit 1; }
t "kernel $KVER"

# Debian released another kernel since the last run: drop everything fetched or built for the old one (its
# debs would be extracted beside the new ones, its modules would not load into the new kernel).
if [ "$(cat "$WORK/kver" 2>/dev/null)" != "$KVER" ]; then
	[ -e "$WORK/kver" ] && t "kernel changed from $(cat "$WORK/kver"): fetching and building again"
	rm -rf "$WORK"/debs/linux-*.deb "$WORK/root" "$WORK/v4l2loopback" "$WORK/dummy_hcd_iso" "$WORK/srcdeb"
	echo "$KVER" >"$WORK/kver"
fi

# 1. download + extract (kernel image, headers, kbuild, v4l2loopback-dkms source)
cd "$WORK/debs"
KBUILD=$(apt-cache depends linux-headers-$KVER | sed -n 's/.*Depends: \(linux-kbuild-[0-9.]*\)$/\1/p' | head -1)
COMMON=$(apt-cache depends linux-headers-$KVER | sed -n 's/.*Depends: \(linux-headers-.*-common.*\)$/\1/p' | head -1)
for p in linux-image-$KVER linux-headers-$KVER $COMMON $KBUILD v4l2loopback-dkms; do
	ls ${p}_*.deb >/dev/null 2>&1 || apt-get download "$p"
done
R=$WORK/root
M_=./lib/modules/$KVER/kernel
if [ ! -e "$R/boot/vmlinuz-$KVER" ]; then
	t "extracting debs"
	rm -rf "$R"; mkdir -p "$R"
	for d in linux-*.deb v4l2loopback-dkms_*.deb; do
		case $d in
		linux-image-*) # only the parts needed (the full image unpacks to ~400 MB)
			dpkg-deb --fsys-tarfile "$d" | tar -x -C "$R" --wildcards './boot/*' \
				"./lib/modules/$KVER/modules.*" "$M_/drivers/media/*" "$M_/drivers/usb/*" \
				"$M_/fs/configfs/*" "$M_/fs/9p/*" "$M_/fs/netfs/*" "$M_/fs/fscache/*" \
				"$M_/net/9p/*" "$M_/drivers/virtio/*" ;;
		*) dpkg -x "$d" "$R" ;;
		esac
	done
fi
# the headers' top Makefile includes the -common tree by absolute /usr/src path: point it at $R
sed -i "s#^include .*/usr/src/linux-headers-#include $R/usr/src/linux-headers-#" "$R/usr/src/linux-headers-$KVER/Makefile"
MODSRC=$R/lib/modules/$KVER
[ -e "$MODSRC/modules.dep" ] || depmod -b "$R" "$KVER"   # the .deb does not ship modules.dep
cp "$R/boot/vmlinuz-$KVER" "$OUT/vmlinuz"

# 2. udevd for the guest (run in the chroot with the host's libraries; its own libsystemd-shared first,
#    since the udev in the archive may be a newer point release than the host's systemd)
U=$WORK/udev
if [ ! -e "$U/bin/udevadm" ]; then
	t "fetching udev"
	(cd "$WORK/debs" && for p in udev libsystemd-shared; do ls ${p}_*.deb >/dev/null 2>&1 || apt-get download "$p"; done)
	rm -rf "$U"; mkdir -p "$U"
	dpkg -x "$WORK"/debs/udev_*.deb "$U"
	dpkg -x "$WORK"/debs/libsystemd-shared_*.deb "$U"
	# udevadm runs as the daemon when called by this name (the package's link is absolute: /bin/udevadm)
	ln -sf bin/udevadm "$U/systemd-udevd"
fi

# 3. v4l2loopback out of tree, patched for 'Z16 ' (0.12.7 silently turns it into BGR4)
LB=$WORK/v4l2loopback
if [ ! -e "$LB/v4l2loopback.ko" ]; then
	t "building v4l2loopback"
	rm -rf "$LB"; cp -r "$R"/usr/src/v4l2loopback-* "$LB"
	patch -d "$LB" -p1 < "$SRC/v4l2loopback-z16.patch"
	make -s -C "$R/usr/src/linux-headers-$KVER" M="$LB" modules
fi

# 4. the gadget-side and loopback feeders (static: they run outside the chroot)
t "compiling feeders"
mkdir -p "$WORK/bin"
for p in loopwriter uvcfeeder; do
	gcc -O2 -Wall -static -I"$SRC" -o "$WORK/bin/$p" "$SRC/$p.c"
done

# 5. initramfs tree
I=$WORK/initramfs
rm -rf "$I"; mkdir -p "$I"/{bin,sbin,dev,proc,sys,tmp,run,etc,host,out}
cp /bin/busybox "$I/bin/busybox"
cp "$WORK"/bin/* "$I/bin/"
cp "$HERE/init.sh" "$I/init"; chmod +x "$I/init"

# kernel modules + dependencies (resolved with the kernel's modules.dep)
WANT="vivid v4l2loopback configfs libcomposite dummy_hcd usb_f_uvc uvcvideo virtio_pci 9pnet_virtio 9p"
M=$I/lib/modules/$KVER
mkdir -p "$M/extra"
cp "$MODSRC"/modules.order "$MODSRC"/modules.builtin* "$M/"
declare -A done_
addmod() { # $1 = path relative to $MODSRC
	local rel=$1
	[ -n "${done_[$rel]:-}" ] && return; done_[$rel]=1
	mkdir -p "$M/$(dirname "$rel")"; cp "$MODSRC/$rel" "$M/$rel"
	local deps; deps=$(grep "^$rel:" "$MODSRC/modules.dep" | cut -d: -f2)
	for d in $deps; do addmod "$d"; done
}
for m in $WANT; do
	case $m in
	v4l2loopback) cp "$LB/v4l2loopback.ko" "$M/extra/";
		for d in $(modinfo -F depends "$LB/v4l2loopback.ko" | tr , ' '); do
			addmod "$(grep -E "/$d\.ko:" "$MODSRC/modules.dep" | cut -d: -f1)"; done ;;
	*) rel=$(grep -E "/${m}\.ko:" "$MODSRC/modules.dep" | cut -d: -f1)
	   [ -n "$rel" ] || { echo "module $m not found"; exit 1; }
	   addmod "$rel" ;;
	esac
done
# stock dummy_hcd has no ISO endpoints, and the UVC gadget streams over ISO only
[ -e "$WORK/dummy_hcd_iso/dummy_hcd.ko" ] || WORK=$WORK KVER=$KVER "$HERE/build-dummy-hcd-iso.sh"
cp "$WORK/dummy_hcd_iso/dummy_hcd.ko" "$M/kernel/drivers/usb/gadget/udc/dummy_hcd.ko"
depmod -b "$I" "$KVER"
t "modules: $(find "$M" -name '*.ko' | wc -l) files, $(du -sh "$M" | cut -f1)"

# 6. pack
(cd "$I" && find . | cpio -o -H newc --quiet | gzip -1) > "$OUT/initrd.img.tmp"
mv "$OUT/initrd.img.tmp" "$OUT/initrd.img"
t "initrd: $(du -h "$OUT/initrd.img" | cut -f1), vmlinuz: $(du -h "$OUT/vmlinuz" | cut -f1)"
