#!/bin/bash
# build-dummy-hcd-iso.sh - build dummy_hcd.ko with a small test patch that adds
# isochronous transfers (stock dummy_hcd exposes no ISO endpoints and fails ISO URBs,
# and the kernel 6.1 UVC gadget (f_uvc) streams over ISO only).
# Source: Debian's linux-source-6.1 package (apt-get download; only one file is extracted).
# Called by build-initramfs.sh (needs the extracted headers in $WORK/root). Adapted from ../shared/vmkit.
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=${WORK:?set WORK to a scratch directory}
KVER=${KVER:-$(ls "$WORK/root/lib/modules" | head -1)}
SRCPKG=linux-source-$(echo "$KVER" | cut -d. -f1,2)
D=$WORK/dummy_hcd_iso
mkdir -p "$WORK/srcdeb" "$D"
cd "$WORK/srcdeb"
ls ${SRCPKG}_*.deb >/dev/null 2>&1 || apt-get download "$SRCPKG"
F=$SRCPKG/drivers/usb/gadget/udc/dummy_hcd.c
[ -e "$F" ] || dpkg-deb --fsys-tarfile ${SRCPKG}_*.deb | tar -x --wildcards "*/$SRCPKG.tar.xz" -O | tar -xJ "$F"
cp "$F" "$D/dummy_hcd.c"
cd "$D"
patch -p0 dummy_hcd.c < "$HERE/src/dummy_hcd-iso.patch"
echo 'obj-m := dummy_hcd.o' > Makefile
make -s -C "$WORK/root/usr/src/linux-headers-$KVER" M="$D" modules
ls -l "$D/dummy_hcd.ko"
