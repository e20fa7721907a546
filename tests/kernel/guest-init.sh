#!/bin/busybox sh
# /init of the kernel-test VM (tests/kernel/kernel-vm builds the initramfs).
# Loads the modules, sets up vivid and gpio-sim, hands the device paths to
# kernel_guest_test in SW_* variables (or why a part is missing in
# SW_*_SKIP), runs it and powers off. The host reads the serial console:
# kernel_guest_test prints "@@SW-RESULT <test> PASS|FAIL|SKIP <reason>",
# this script "@@SW-DONE <exit code>" at the end.
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t tmpfs tmpfs /tmp
echo "@@SW-BOOTED $(cut -d' ' -f1 /proc/uptime)"

. /etc/sw/env  # SW_GPIO_SKIP: set by the host when gpio-sim could not be built

# Modules in dependency order, one "file [parameters]" per line.
load_modules() {
  while read -r file params; do
    [ -n "$file" ] || continue
    if ! out=$(insmod "/lib/sw-modules/$file" $params 2>&1); then
      echo "insmod $file: $out"
      return 1
    fi
  done < /etc/sw/modules.txt
}
if ! why=$(load_modules); then
  echo "module loading failed: $why"
  export SW_V4L2_SKIP="$why" SW_LOOP_SKIP="$why"
  [ -n "$SW_GPIO_SKIP" ] || export SW_GPIO_SKIP="$why"
fi

# vivid instances: 0 and 1 S-Video capture (the cameras), 2 HDMI capture + output (the loop).
node_named() {
  for d in /sys/class/video4linux/video*; do
    [ "$(cat "$d/name" 2>/dev/null)" = "$1" ] && { echo "/dev/$(basename "$d")"; return 0; }
  done
  return 1
}
if [ -z "$SW_V4L2_SKIP" ]; then
  SW_VIDEO_A=$(node_named vivid-000-vid-cap) && SW_VIDEO_B=$(node_named vivid-001-vid-cap) &&
    export SW_VIDEO_A SW_VIDEO_B || export SW_V4L2_SKIP="vivid loaded but its capture nodes are missing: $(cat /sys/class/video4linux/*/name 2>/dev/null | tr '\n' ' ')"
  SW_LOOP_CAP=$(node_named vivid-002-vid-cap) && SW_LOOP_OUT=$(node_named vivid-002-vid-out) &&
    export SW_LOOP_CAP SW_LOOP_OUT || export SW_LOOP_SKIP="vivid loaded but instance 2 (HDMI loop) is missing"
fi

# gpio-sim: one bank of 4 lines, configured through configfs.
if [ -z "$SW_GPIO_SKIP" ]; then
  mount -t configfs none /sys/kernel/config
  sim=/sys/kernel/config/gpio-sim/spinewatch
  if mkdir "$sim" && mkdir "$sim/bank0" && echo 4 > "$sim/bank0/num_lines" && echo 1 > "$sim/live"; then
    chip=$(cat "$sim/bank0/chip_name")
    dev=$(cat "$sim/dev_name")
    export SW_GPIO_CHIP="/dev/$chip" SW_GPIO_SYSFS="/sys/devices/platform/$dev/$chip"
    [ -d "$SW_GPIO_SYSFS/sim_gpio0" ] || export SW_GPIO_SKIP="gpio-sim is live but $SW_GPIO_SYSFS/sim_gpio0 is missing"
  else
    export SW_GPIO_SKIP="gpio-sim: configuring $sim through configfs failed"
  fi
fi

export SW_PHANTOM=/data/phantom SW_CLI=/bin/spinewatch SW_TMP=/tmp HOME=/tmp
cd /tmp
echo "@@SW-START $(cut -d' ' -f1 /proc/uptime)"
/bin/kernel_guest_test --gtest_brief=1 $SW_GTEST_ARGS
rc=$?
echo "@@SW-DONE $rc $(cut -d' ' -f1 /proc/uptime)"
sync
poweroff -f
