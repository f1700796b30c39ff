#!/bin/bash
# Plays the UI monkey with a fresh seed in each of PROCESSES processes side by side for SECONDS, then prints
# each one's seed, actions and exit status, and the total. A failed run's log is kept in LOGDIR.
# Use: scripts/monkey-farm.sh TEST_UI PROCESSES SECONDS [LOGDIR]
#   TEST_UI: the built test_ui (build/tests/ui/test_ui), or one unpacked from a bundle made with
#   ../shared/tools/bundle-runtime.sh for a machine without Debian's packages. Such a bundle stubs FFmpeg
#   out; export OPENCV_VIDEOIO_PRIORITY_FFMPEG=0 there, so that a Stray export fails cleanly rather than
#   calling into the stub.
set -u
test_ui=$1; processes=$2; seconds=$3; logdir=${4:-/tmp/monkey-farm}
mkdir -p "$logdir"; work=$(mktemp -d)
for i in $(seq 1 "$processes"); do
  (cd "$work" && DC_MONKEY_SECONDS=$seconds "$test_ui" --gtest_filter='MonkeyTest.AFreshSeed*' \
     > "$work/monkey-$i.log" 2>&1; echo "rc $?" >> "$work/monkey-$i.log") &
done
wait
total=0; failed=0
for i in $(seq 1 "$processes"); do
  log=$work/monkey-$i.log
  seed=$(sed -n 's/^monkey: seed //p' "$log"); n=$(sed -n 's/^monkey: \([0-9]*\) actions$/\1/p' "$log")
  rc=$(sed -n 's/^rc //p' "$log")
  echo "monkey $i: seed $seed, ${n:-?} actions, rc $rc"
  total=$((total + ${n:-0}))
  [ "$rc" = 0 ] || { failed=$((failed + 1)); cp "$log" "$logdir/"; }
done
rm -rf "$work"
echo "total $total actions in $processes monkeys x $seconds s, $failed failed"
[ "$failed" = 0 ]
