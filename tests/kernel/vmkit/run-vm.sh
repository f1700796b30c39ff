#!/bin/bash
# run-vm.sh - boot the kernel-tier VM (build-initramfs.sh) once and run the scenarios in it.
# usage: run-vm.sh LOG        scenarios from $TESTS (comma list of uvc,loopback,vivid; default all)
# Env: OUT (vmlinuz + initrd.img), BUILD (the host build directory with depthcloud and kernel_guest_test),
#      UDEV (the extracted udev of build-initramfs.sh), KVM=auto|1|0, TIMEOUT (s),
#      FROM_TMP=1: run the binaries from links to them in a fresh directory under /tmp (see below).
# The guest mounts the host's / read-only over virtio-9p and runs our binaries from BUILD in a chroot.
# BUILD and UDEV are also exported on their own and mounted at their host paths over everything else
# the guest mounts, so no guest mount (its /run, its /dev) can hide them wherever the checkout lives.
# Exit status 0 when the guest got to the end ("ALL-DONE"); each scenario's results are RESULT lines and
# gtest lines in LOG, which the kernel_* tests check one by one.
set -uo pipefail
LOG=${1:?usage: run-vm.sh LOG}
OUT=${OUT:?} BUILD=${BUILD:?} UDEV=${UDEV:?}
TESTS=${TESTS:-uvc,loopback,vivid}

# A fresh clone is often under /tmp, which the guest once hid under a tmpfs. With FROM_TMP=1 (as CTest
# runs it) every scenario runs from such a directory: the proof costs two links, not a second boot.
if [ "${FROM_TMP:-0}" = 1 ]; then
	STAGE=$(mktemp -d /tmp/depthcloud-kernel.XXXXXX) || exit 1
	trap 'rm -rf "$STAGE"' EXIT
	for f in tool/depthcloud tests/kernel/kernel_guest_test; do
		mkdir -p "$STAGE/$(dirname "$f")"
		ln "$BUILD/$f" "$STAGE/$f" 2>/dev/null || cp "$BUILD/$f" "$STAGE/$f" || exit 1
	done
	BUILD=$STAGE
fi

# One virtio-9p export per directory the guest reads, mounted at the same path (kernel cmdline
# dcexport=TAG=PATH,...): neither the cmdline nor -virtfs can carry blanks or commas in a path.
BUILD=$(realpath "$BUILD") && UDEV=$(realpath "$UDEV") || exit 1
EXPORT_ARGS=() EXPORTS=""
for dir in "$BUILD" "$UDEV"; do
	case $dir in *[[:space:],=]*)
		echo "run-vm.sh: '$dir' has a blank, comma or '=' in its path, which the guest cannot mount" >&2; exit 1 ;;
	esac
	tag=dc${#EXPORT_ARGS[@]}
	EXPORT_ARGS+=(-virtfs "local,path=$dir,mount_tag=$tag,security_model=none,readonly=on")
	EXPORTS=${EXPORTS:+$EXPORTS,}$tag=$dir
done
KVM=${KVM:-auto}
if [ "$KVM" = auto ]; then
	# /dev/kvm backed by PVM (nested_pvm, as on some cloud VMs) only runs PVM-enabled guest kernels: a stock
	# Debian kernel hangs in its decompressor there, so use TCG.
	if [ -r /dev/kvm ] && [ -w /dev/kvm ] && [ ! -d /sys/module/kvm_pvm ]; then KVM=1; else KVM=0; fi
fi
if [ "$KVM" = 1 ]; then ACCEL="-enable-kvm -cpu host"; TIMEOUT=${TIMEOUT:-300}
else ACCEL="-accel tcg"; TIMEOUT=${TIMEOUT:-900}; fi
echo "booting (kvm=$KVM, timeout ${TIMEOUT}s, tests=$TESTS, binaries from $BUILD), serial log: $LOG"
START=$(date +%s.%N)
timeout --foreground -k 5 "$TIMEOUT" qemu-system-x86_64 $ACCEL -m 2048 -smp 2 -nographic -no-reboot \
	-kernel "$OUT/vmlinuz" -initrd "$OUT/initrd.img" -nic none \
	-virtfs local,path=/,mount_tag=hostroot,security_model=none,readonly=on "${EXPORT_ARGS[@]}" \
	-append "console=ttyS0 panic=-1 loglevel=4 rtest=$TESTS dcbuild=$BUILD dcudev=$UDEV dcexport=$EXPORTS" \
	< /dev/null > "$LOG" 2>&1
RC=$?
END=$(date +%s.%N)
grep -aE '^(RESULT|METRIC|=== |--- )|\[ +(OK|FAILED) +\]' "$LOG" | tr -d '\r'
awk -v a="$START" -v b="$END" -v rc="$RC" 'BEGIN{printf "wall time: %.1f s (qemu rc=%d)\n", b-a, rc}'
grep -aq 'ALL-DONE' "$LOG"
