#!/bin/busybox sh
# /init of the kernel-tier VM. Kernel cmdline: rtest=uvc,loopback,vivid  dcbuild=HOST_BUILD_DIR
# dcudev=HOST_UDEV_DIR dcexport=TAG=PATH,... The host's / is mounted read-only at /host (virtio-9p) and our
# binaries run there in a chroot with the host's libraries; the feeders run outside it. Each dcexport
# directory is a 9p export of its own, mounted last at its host path so that nothing mounted here hides it.
# The host's /tmp stays visible (a checkout may live there); the chroot's scratch is $SCRATCH on the guest's
# /run. Prints "RESULT name PASS|FAIL" lines, our gtest output, and "=== ALL-DONE failures=N", then powers
# off. Adapted from ../shared/vmkit.
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
mount -t tmpfs run /run
echo 1 > /proc/sys/kernel/printk_ratelimit 2>/dev/null
up() { cut -d' ' -f1 /proc/uptime; }
arg() { sed -n "s/.*[ ]$1=\([^ ]*\).*/\1/p" /proc/cmdline; }
TESTS=$(arg rtest); [ -n "$TESTS" ] || TESTS=uvc,loopback,vivid
BUILD=$(arg dcbuild)
UDEV=$(arg dcudev)
EXPORTS=$(arg dcexport)
SCRATCH=/run/depthcloud-kernel
VID=8086 PID=0b07
SKIP_EVERY=5 # while the guest test asks, the depth feeder sends every 5th frame short (uvcfeeder -k)
echo "=== guest up at $(up)s, kernel $(uname -r), tests: $TESTS"
FAILS=0
result() { echo "RESULT $1 $2 (t=$(up)s)"; [ "$2" = PASS ] || FAILS=$((FAILS+1)); }
finish() { echo "=== ALL-DONE failures=$FAILS uptime=$(up)s"; sync; poweroff -f; }

# --- the host's root, and a chroot on it with this guest's /proc, /sys, /dev
modprobe virtio_pci && modprobe 9pnet_virtio && modprobe 9p || { result host-mount FAIL; finish; }
mkdir -p /host
mount -t 9p -o trans=virtio,version=9p2000.L,ro,cache=loose,msize=512000 hostroot /host || { result host-mount FAIL; finish; }
mount -t proc proc /host/proc && mount -t sysfs sys /host/sys && mount -t devtmpfs dev /host/dev &&
	mount -t tmpfs run /host/run && mkdir -p /host$SCRATCH || { result chroot-mounts FAIL; finish; }
modprobe configfs && mount -t configfs none /sys/kernel/config && mount -t configfs none /host/sys/kernel/config
for e in $(echo "$EXPORTS" | tr , ' '); do
	dir=${e#*=}
	mkdir -p "/host$dir" 2>/dev/null # exists already unless it is under a guest mount (/run)
	mount -t 9p -o trans=virtio,version=9p2000.L,ro,cache=loose,msize=512000 "${e%%=*}" "/host$dir" ||
		{ result export-mount FAIL; finish; }
done
in_host() { chroot /host /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=$SCRATCH TMPDIR=$SCRATCH "$@"; }
GUEST_TEST=$BUILD/tests/kernel/kernel_guest_test
DEPTHCLOUD=$BUILD/tool/depthcloud
# One clear failure, not one per scenario, when the build directory is not what the chroot sees.
if [ -x /host$GUEST_TEST ] && [ -x /host$DEPTHCLOUD ]; then result build-dir PASS; else
	echo "the chroot sees no $GUEST_TEST or $DEPTHCLOUD"; result build-dir FAIL; fi
# libusb learns of hotplug from udevd (no rules needed: it only relays the kernel's events)
in_host /usr/bin/env LD_LIBRARY_PATH=$UDEV/usr/lib/x86_64-linux-gnu/systemd $UDEV/systemd-udevd --daemon \
	&& result udevd PASS || result udevd FAIL

# /dev/videoN whose driver is $1 and index $2 (0 = main capture node), and with $3 on a USB interface of
# that number (uvcvideo: each UVC function of the gadget is a camera of its own on its own interfaces)
find_node() {
	for d in /sys/class/video4linux/video*; do
		[ -e "$d" ] || continue
		drv=$(basename "$(readlink "$d/device/driver")" 2>/dev/null)
		[ -z "$3" ] || [ "$(cat "$d/device/bInterfaceNumber" 2>/dev/null)" = "$3" ] || continue
		[ "$drv" = "$1" ] && [ "$(cat "$d/index")" = "${2:-0}" ] && { echo /dev/$(basename "$d"); return 0; }
	done
	return 1
}

# A UVC function $1 of gadget $G streaming one uncompressed format: guidFormat $2 (16 bytes as printf
# escapes), 16 bits per pixel, $3 x $4 pixels, nominally 30 fps.
add_uvc_function() {
	F=$G/functions/$1
	mkdir $F || return 1
	mkdir $F/control/header/h
	ln -s $F/control/header/h $F/control/class/fs/h
	ln -s $F/control/header/h $F/control/class/ss/h
	U=$F/streaming/uncompressed/u
	mkdir -p $U/f
	printf "$2" > $U/guidFormat
	echo 16 > $U/bBitsPerPixel 2>/dev/null
	echo $3 > $U/f/wWidth; echo $4 > $U/f/wHeight
	echo $(($3 * $4 * 2)) > $U/f/dwMaxVideoFrameBufferSize
	echo $(($3 * $4 * 2 * 8 * 30)) > $U/f/dwMinBitRate; echo $(($3 * $4 * 2 * 8 * 30)) > $U/f/dwMaxBitRate
	echo 333333 > $U/f/dwDefaultFrameInterval; echo 333333 > $U/f/dwFrameInterval
	mkdir $F/streaming/header/h
	ln -s $U $F/streaming/header/h/u
	ln -s $F/streaming/header/h $F/streaming/class/fs/h
	ln -s $F/streaming/header/h $F/streaming/class/hs/h
	ln -s $F/streaming/header/h $F/streaming/class/ss/h
	echo 3072 > $F/streaming_maxpacket  # 3x1024 high-bandwidth ISO (the patched dummy_hcd)
	ln -s $F $G/configs/c.1/$1
}

setup_uvc_gadget() {
	modprobe dummy_hcd && modprobe libcomposite && modprobe usb_f_uvc || return 1
	G=/sys/kernel/config/usb_gadget/depthcam
	mkdir $G && cd $G || return 1
	echo 0x$VID > idVendor; echo 0x$PID > idProduct; echo 0x0200 > bcdUSB; echo 0x0100 > bcdDevice
	echo 0xEF > bDeviceClass; echo 0x02 > bDeviceSubClass; echo 0x01 > bDeviceProtocol  # IAD
	mkdir strings/0x409
	echo "Fake Depth Inc" > strings/0x409/manufacturer
	echo "Virtual Z16 Depth Camera" > strings/0x409/product
	echo "VDC0001" > strings/0x409/serialnumber
	mkdir configs/c.1 configs/c.1/strings/0x409
	echo "UVC" > configs/c.1/strings/0x409/configuration; echo 500 > configs/c.1/MaxPower
	# Two sensors, as a RealSense has: depth on uvc.0 (interfaces 0 and 1), colour on uvc.1 (2 and 3).
	# guidFormat Z16 = 5a313620-0000-0010-8000-00aa00389b71, YUY2 = 32595559-0000-0010-8000-00aa00389b71
	# (mixed-endian GUID bytes)
	add_uvc_function uvc.0 '\x5a\x31\x36\x20\x00\x00\x10\x00\x80\x00\x00\xaa\x00\x38\x9b\x71' 640 480 &&
	add_uvc_function uvc.1 '\x59\x55\x59\x32\x00\x00\x10\x00\x80\x00\x00\xaa\x00\x38\x9b\x71' 320 240 ||
		return 1
	UDC=$(ls /sys/class/udc | head -1)
	echo $UDC > $G/UDC || return 1
	cd /
}

start_uvc() {
	echo "--- UVC gadget on dummy_hcd -> uvcvideo"
	setup_uvc_gadget || { dmesg | tail -20; result uvc-gadget FAIL; return 1; }
	modprobe uvcvideo || { result uvc-gadget FAIL; return 1; }
	echo "uvcvideo nodrop=$(cat /sys/module/uvcvideo/parameters/nodrop 2>/dev/null)" # how it treats a short frame
	# The gadget connects once every function's node is open: both feeders first.
	uvcfeeder -n 0 -s 1 -r 10 -k $SKIP_EVERY > /tmp/feeder.log 2>&1 &
	FEEDER=$!
	uvcfeeder -n 1 -s 3 -c -w 320 -h 240 -r 10 > /tmp/colour-feeder.log 2>&1 &
	i=0; while ! { UVC_NODE=$(find_node uvcvideo 0 00) && COLOUR_NODE=$(find_node uvcvideo 0 02); } &&
		[ $i -lt 200 ]; do sleep 0.1; i=$((i+1)); done
	[ -n "$UVC_NODE" ] && [ -n "$COLOUR_NODE" ] ||
		{ cat /tmp/feeder.log /tmp/colour-feeder.log; dmesg | tail -30; result uvc-gadget FAIL; return 1; }
	result uvc-gadget PASS
	ENV="$ENV VIDEO=$UVC_NODE COLOUR_VIDEO=$COLOUR_NODE UDC_FILE=/sys/kernel/config/usb_gadget/depthcam/UDC"
	ENV="$ENV UDC_NAME=$UDC FEEDER_PID=$FEEDER FEEDER_SKIP_EVERY=$SKIP_EVERY"
	FILTER="$FILTER:Uvc.*"
}

LOOP_ARGS="devices=1 video_nr=10 exclusive_caps=1 card_label=loopdepth"
start_loopwriter() {
	loopwriter -d /dev/video10 -f 'Z16 ' -r 10 > /tmp/lw.log 2>&1 &
	LOOPWRITER=$!
	sleep 1
}

start_loopback() {
	echo "--- v4l2loopback (patched for Z16)"
	modprobe v4l2loopback $LOOP_ARGS || { result loopback-load FAIL; return 1; }
	start_loopwriter
	cat /tmp/lw.log
	ENV="$ENV LOOP_NODE=/dev/video10 LOOP_REQUEST=$SCRATCH/loopback-request"
	FILTER="$FILTER:Loopback.*"
	loopback_plugger &
}

# Unplugs ("unplug": the feeder stopped, the module removed) and replugs the loopback camera when the guest
# test writes the request file, which is removed once done: its module loads here, outside the chroot.
loopback_plugger() {
	request=/host$SCRATCH/loopback-request
	while :; do
		case $(cat $request 2>/dev/null) in
		unplug)
			kill $LOOPWRITER
			i=0; while ! rmmod v4l2loopback 2>/dev/null && [ $i -lt 50 ]; do sleep 0.1; i=$((i+1)); done
			rm -f $request ;;
		replug)
			modprobe v4l2loopback $LOOP_ARGS && start_loopwriter
			rm -f $request ;;
		esac
		sleep 0.1
	done
}

start_vivid() {
	echo "--- vivid (Y16 as depth)"
	modprobe vivid n_devs=1 node_types=0x1 input_types=0x0 || { result vivid-load FAIL; return 1; }
	VIVID_NODE=$(find_node vivid 0) || { result vivid-load FAIL; return 1; }
	# No on-screen text, so every frame of the test pattern is the same: a raw frame captured by
	# v4l2-ctl is the independent reference for what our code reads.
	in_host v4l2-ctl -d $VIVID_NODE -c osd_text_mode=2 &&
	in_host v4l2-ctl -d $VIVID_NODE --set-fmt-video=width=640,height=480,pixelformat='Y16 ' --stream-mmap \
		--stream-count=2 --stream-to=$SCRATCH/vivid.raw && result vivid-reference PASS || result vivid-reference FAIL
	# v4l2-ctl's listing of every control is the reference for ours.
	in_host v4l2-ctl -d $VIVID_NODE --list-ctrls-menus > /host$SCRATCH/vivid-ctrls.txt &&
		result vivid-controls-reference PASS || result vivid-controls-reference FAIL
	ENV="$ENV VIVID_NODE=$VIVID_NODE VIVID_RAW=$SCRATCH/vivid.raw VIVID_CTRLS=$SCRATCH/vivid-ctrls.txt"
	FILTER="$FILTER:Vivid.*"
}

# `depthcloud devices` lists the camera with its identity and its Z16 mode.
check_devices_command() {
	in_host $DEPTHCLOUD devices > /tmp/devices.txt 2>&1; rc=$?
	sed 's/^/  devices: /' /tmp/devices.txt
	if [ $rc = 0 ] && grep -q "usb 8086:0b07" /tmp/devices.txt && grep -q "Virtual Z16 Depth Camera" /tmp/devices.txt &&
		grep -q "depth    $UVC_NODE" /tmp/devices.txt && grep -q "'Z16 ' 640x480@30" /tmp/devices.txt &&
		grep -q "serial \"VDC0001\"" /tmp/devices.txt; then result devices-command PASS; else result devices-command FAIL; fi
}

# The whole application, headless, on the USB camera.
check_headless() {
	out=$SCRATCH/headless
	in_host $DEPTHCLOUD --source usb:$VID:$PID --headless --frames 3 --out $out > /tmp/headless.log 2>&1; rc=$?
	sed 's/^/  headless: /' /tmp/headless.log
	ls -l /host$out 2>&1 | sed 's/^/  headless: /'
	sed 's/^/  summary.json: /' /host$out/summary.json 2>/dev/null
	# the colour node is the camera's own, and no calibration relates it to depth: it must say so
	if [ $rc = 0 ] && [ -s /host$out/cloud.png ] && [ -s /host$out/depth.png ] &&
		grep -q "colours not registered" /tmp/headless.log &&
		grep -Eq '"frames": ([3-9]|[1-9][0-9]+)([^0-9]|$)' /host$out/summary.json &&
		grep -q '"depthWidth": 640' /host$out/summary.json &&
		grep -q '"latencyMs": [0-9]' /host$out/summary.json
	then result headless-usb PASS; else result headless-usb FAIL; fi
}

# The whole application on the camera's two sensors, with the two-sensor calibration the guest test wrote:
# registered colours all the way to the panels, so neither the unregistered colours nor the approximate
# geometry are reported.
check_headless_rig() {
	out=$SCRATCH/headless-rig
	[ -s /host$SCRATCH/rig.yaml ] || { echo "no rig.yaml from the guest test"; result headless-usb-rig FAIL; return; }
	in_host $DEPTHCLOUD --source usb:$VID:$PID:calib=$SCRATCH/rig.yaml --headless --frames 3 --out $out \
		> /tmp/headless-rig.log 2>&1; rc=$?
	sed 's/^/  headless-rig: /' /tmp/headless-rig.log
	echo "  headless-rig: exit status $rc"
	ls -l /host$out 2>&1 | sed 's/^/  headless-rig: /'
	sed 's/^/  headless-rig summary.json: /' /host$out/summary.json 2>/dev/null
	# at least the 3 frames asked for: on a busy machine the run goes on until the camera's image arrives
	if [ $rc = 0 ] && [ -s /host$out/cloud.png ] && [ -s /host$out/camera.png ] &&
		grep -q "wrote .*camera.png" /tmp/headless-rig.log &&
		grep -Eq '"frames": ([3-9]|[1-9][0-9]+)([^0-9]|$)' /host$out/summary.json && ! grep -q "not registered" /tmp/headless-rig.log &&
		! grep -q "approximate geometry" /tmp/headless-rig.log
	then result headless-usb-rig PASS; else result headless-usb-rig FAIL; fi
}

# `depthcloud controls` sets two of vivid's controls (v4l2-ctl reads them back) and refuses a value out of
# range, naming it, without setting anything. vivid was unbound and bound again by then: its node is found
# again.
check_controls() {
	node=$(find_node vivid 0) || { result controls-command FAIL; return; }
	in_host $DEPTHCLOUD controls --source v4l2:$node --set brightness=200 --set contrast=0x20 > /tmp/controls.txt 2>&1
	rc=$?
	head -12 /tmp/controls.txt | sed 's/^/  controls: /'
	b=$(in_host v4l2-ctl -d $node -C brightness) c=$(in_host v4l2-ctl -d $node -C contrast)
	echo "  controls: exit status $rc; v4l2-ctl reads $b, $c"
	in_host $DEPTHCLOUD controls --source v4l2:$node --set contrast=64 --set brightness=300 > /tmp/controls-bad.txt 2>&1
	bad=$?
	sed 's/^/  controls: /' /tmp/controls-bad.txt
	b2=$(in_host v4l2-ctl -d $node -C brightness) c2=$(in_host v4l2-ctl -d $node -C contrast)
	echo "  controls: exit status $bad; v4l2-ctl reads $b2, $c2"
	if [ $rc = 0 ] && [ "$b" = "brightness: 200" ] && [ "$c" = "contrast: 32" ] &&
		grep -Eq "^ +brightness +int .*: 200" /tmp/controls.txt && [ $bad = 2 ] &&
		grep -q "'brightness' takes 0..255, not 300" /tmp/controls-bad.txt &&
		[ "$b2" = "brightness: 200" ] && [ "$c2" = "contrast: 32" ]
	then result controls-command PASS; else result controls-command FAIL; fi
	check_controls_preset "$node"
}

# --save writes the values as a preset; after v4l2-ctl changes them, --load sets them again.
check_controls_preset() {
	node=$1
	rm -f /host$SCRATCH/preset.json
	in_host $DEPTHCLOUD controls --source v4l2:$node --save $SCRATCH/preset.json > /dev/null 2>&1
	saved=$?
	in_host v4l2-ctl -d $node -c brightness=10,contrast=100
	in_host $DEPTHCLOUD controls --source v4l2:$node --load $SCRATCH/preset.json > /tmp/controls-load.txt 2>&1
	loaded=$?
	b=$(in_host v4l2-ctl -d $node -C brightness) c=$(in_host v4l2-ctl -d $node -C contrast)
	echo "  controls: --save exit status $saved, --load exit status $loaded; v4l2-ctl reads $b, $c"
	if [ $saved = 0 ] && [ $loaded = 0 ] && grep -q '"name": "brightness"' /host$SCRATCH/preset.json &&
		[ "$b" = "brightness: 200" ] && [ "$c" = "contrast: 32" ]
	then result controls-preset PASS; else result controls-preset FAIL; fi
}

# The lines `depthcloud controls` prints for the controls of a `v4l2-ctl --list-ctrls-menus` listing ($1), one
# extended regular expression each: "  key type min..max step S default D: V [flags]" and a menu's entries.
# v4l2-ctl prints no step for a menu.
ours_from_v4l2ctl() {
	awk 'function f(name,  i) { for (i = 4; i <= NF; i++) if (index($i, name "=") == 1) return substr($i, length(name) + 2) }
	/ 0x[0-9a-f]+ \(/ { type = $3; gsub(/[()]/, "", type); step = f("step"); if (step == "") step = "[0-9]+"
		printf "^ +%s +%s +%s\\.\\.%s step %s default %s: %s( .*)?$\n", $1, type, f("min"), f("max"), step, f("default"), f("value") }
	/^[ \t]+[0-9]+: / { sub(/^[ \t]+/, ""); printf "^ +%s$\n", $0 }' "$1"
}

# `depthcloud controls` on the USB camera lists its depth node's controls as v4l2-ctl does: the feeder's
# brightness (-64..64, default 0) and the auto-exposure mode as a menu of the modes the feeder offers.
check_uvc_controls_listed() {
	node=$1
	in_host v4l2-ctl -d $node --list-ctrls-menus > /tmp/uvc-ctrls.txt 2>&1
	sed 's/^/  uvc controls: v4l2-ctl: /' /tmp/uvc-ctrls.txt
	in_host $DEPTHCLOUD controls --source usb:$VID:$PID > /tmp/uvc-controls.txt 2>&1; rc=$?
	sed 's/^/  uvc controls: /' /tmp/uvc-controls.txt
	# the depth node's part of our listing: from its line to the next node's
	awk -v node=$node '$1 == node { on = 1; next } /^\// { on = 0 } on' /tmp/uvc-controls.txt > /tmp/uvc-ours.txt
	ours_from_v4l2ctl /tmp/uvc-ctrls.txt > /tmp/uvc-expected.txt
	missing=0
	while read -r line; do
		grep -Eq -- "$line" /tmp/uvc-ours.txt || { echo "  uvc controls: none of ours is $line"; missing=$((missing+1)); }
	done < /tmp/uvc-expected.txt
	theirs=$(grep -c ' 0x[0-9a-f]* (' /tmp/uvc-ctrls.txt) mine=$(grep -Ec '^    [a-z0-9_]+ ' /tmp/uvc-ours.txt)
	echo "  uvc controls: exit status $rc; v4l2-ctl lists $theirs controls, we list $mine, $missing unlike"
	if [ $rc = 0 ] && [ $missing = 0 ] && [ "$theirs" = "$mine" ] &&
		grep -Eq "brightness 0x00980900 \(int\) +: min=-64 max=64 step=1 default=0 " /tmp/uvc-ctrls.txt &&
		grep -Eq "auto_exposure 0x009a0901 \(menu\) +: min=0 max=3 default=3 " /tmp/uvc-ctrls.txt &&
		grep -Eq "^[[:space:]]+1: Manual Mode$" /tmp/uvc-ctrls.txt &&
		grep -Eq "^[[:space:]]+3: Aperture Priority Mode$" /tmp/uvc-ctrls.txt &&
		! grep -Eq "^[[:space:]]+0: Auto Mode$" /tmp/uvc-ctrls.txt
	then result uvc-controls-listed PASS; else result uvc-controls-listed FAIL; fi
}

# The last value the depth feeder took for a control ("brightness", "auto-exposure mode"), from its log.
feeder_value() { sed -n "s/^feeder: SET_CUR $1 = \(-*[0-9]*\)$/\1/p" /tmp/feeder.log | tail -1; }

# --set, from the defaults the guest test left, goes through uvcvideo to the depth feeder (its log says what
# it took; the colour feeder's brightness is another sensor's and stays) and v4l2-ctl reads it back; a value
# out of range is refused naming the control (exit 2) and reaches nobody.
check_uvc_controls_set() {
	node=$1
	in_host $DEPTHCLOUD controls --source usb:$VID:$PID --set brightness=-23 --set auto_exposure=1 \
		> /tmp/uvc-set.txt 2>&1; rc=$?
	b=$(in_host v4l2-ctl -d $node -C brightness) a=$(in_host v4l2-ctl -d $node -C auto_exposure)
	fb=$(feeder_value brightness) fa=$(feeder_value "auto-exposure mode")
	echo "  uvc controls: --set exit status $rc; v4l2-ctl reads $b, $a; the feeder took brightness $fb, mode $fa"
	if [ $rc = 0 ] && [ "$b" = "brightness: -23" ] && [ "$a" = "auto_exposure: 1 (Manual Mode)" ] && [ "$fb" = -23 ] &&
		[ "$fa" = 1 ] && ! grep -q "SET_CUR brightness = -23" /tmp/colour-feeder.log
	then result uvc-controls-set PASS; else result uvc-controls-set FAIL; fi
	in_host $DEPTHCLOUD controls --source usb:$VID:$PID --set brightness=65 > /tmp/uvc-bad.txt 2>&1; bad=$?
	sed 's/^/  uvc controls: /' /tmp/uvc-bad.txt
	b=$(in_host v4l2-ctl -d $node -C brightness) fb=$(feeder_value brightness)
	echo "  uvc controls: exit status $bad; v4l2-ctl reads $b; the feeder's brightness $fb"
	if [ $bad = 2 ] && grep -q "'brightness' takes -64..64, not 65" /tmp/uvc-bad.txt &&
		[ "$b" = "brightness: -23" ] && [ "$fb" = -23 ]
	then result uvc-controls-out-of-range PASS; else result uvc-controls-out-of-range FAIL; fi
}

check_uvc_controls() {
	node=$(find_node uvcvideo 0 00) || { result uvc-controls-listed FAIL; return; }
	check_uvc_controls_listed $node
	check_uvc_controls_set $node
}

# Everything is set up first and our programs start once each: under TCG, loading their libraries over
# 9p is what takes longest.
ENV="" FILTER=""
UVC=0 VIVID=0
for t in $(echo $TESTS | tr , ' '); do
	case $t in
	uvc) start_uvc && UVC=1 ;;
	loopback) start_loopback ;;
	vivid) start_vivid && VIVID=1 ;;
	shell) setsid cttyhack sh ;;
	esac
done
[ $UVC = 1 ] && check_devices_command
case $FILTER in *Loopback*Vivid*) FILTER="$FILTER:Virtual.*" ;; esac # both virtual cameras are up
[ -n "$FILTER" ] && in_host /usr/bin/env $ENV $GUEST_TEST --gtest_filter="${FILTER#:}" --gtest_color=no
[ $UVC = 1 ] && check_headless
[ $UVC = 1 ] && check_headless_rig
[ $UVC = 1 ] && check_uvc_controls
[ $VIVID = 1 ] && check_controls
[ $UVC = 1 ] && tail -5 /tmp/feeder.log /tmp/colour-feeder.log
finish
