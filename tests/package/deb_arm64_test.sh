#!/usr/bin/env bash
# The arm64 package of a cross build tree (the arm64 preset):
#  1. cpack packages the build as it is into a scratch directory;
#  2. Architecture is arm64, and Depends names systemd and, for every
#     shared library spinewatchd and spinewatch need (their NEEDED
#     entries), the package the sysroot's shlibs files give for it;
#  3. the programs in the package are aarch64 ELF files, and they run:
#     unpacked into a scratch root, under qemu-user with the sysroot's
#     libraries, the CLI prints its version and accepts the packaged
#     configuration (check --config), the daemon prints its annotated one.
# Installing it (accounts, conffile, the daemon serving postures) is the
# amd64 package's test (deb_install_test.sh): the maintainer scripts and
# the install rules are the same for both architectures.
# Usage: deb_arm64_test.sh BUILD_DIR SYSROOT EMULATOR [ARGS...]. Exit 77:
# cannot run here.
set -euo pipefail

build=$1
sysroot=$2
shift 2
emulator=("$@")
export LC_ALL=C

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
for tool in cpack dpkg-deb aarch64-linux-gnu-objdump; do
  command -v "$tool" >/dev/null || { echo "SKIP: $tool is not installed"; exit 77; }
done

# 1. Package.
cpack --config "$build/CPackConfig.cmake" -B "$work/out" >"$work/cpack.log" 2>&1 ||
  fail "cpack failed: $(cat "$work/cpack.log")"
shopt -s nullglob
debs=("$work"/out/spinewatch_*_arm64.deb)
[ ${#debs[@]} -eq 1 ] || fail "expected one spinewatch_*_arm64.deb in $work/out, found: $(ls "$work/out")"
deb=${debs[0]}
echo "package: $(basename "$deb"), $(stat -c %s "$deb") bytes"

# 2. Control fields.
field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Architecture)" = arm64 ] || fail "Architecture: $(field Architecture)"
depends=$(field Depends)
echo "Depends: $depends"
depends_names=" $(echo "$depends" | sed -E 's/\([^)]*\)//g; s/[,|]/ /g') "
[[ $depends_names == *" systemd "* ]] || fail "Depends lacks systemd: $depends"
shlibs=$sysroot/var/lib/spinewatch-sysroot/shlibs
count=0
for binary in "$build/daemon/spinewatchd" "$build/tools/spinewatch"; do
  for soname in $(aarch64-linux-gnu-objdump -p "$binary" | awk '$1 == "NEEDED" { print $2 }'); do
    # libfoo.so.6 -> "libfoo 6"; libfoo-1.2.so -> "libfoo-1.2" (shlibs' two forms).
    if [[ $soname =~ ^(.*)\.so\.(.*)$ ]]; then
      key="${BASH_REMATCH[1]} ${BASH_REMATCH[2]}"
    else
      key="${soname%.so} "
    fi
    package=$(awk -v k="$key" 'index($0, k " ") == 1 || $1 " " $2 == k { print $3; exit }' "$shlibs")
    [ -n "$package" ] || fail "$(basename "$binary") needs $soname, which no shlibs file in the sysroot names"
    [[ $depends_names == *" $package "* ]] ||
      fail "$(basename "$binary") needs $soname from $package, which Depends does not name: $depends"
    count=$((count + 1))
  done
done
echo "Depends names the package of each of the $count libraries the programs need"

# 3. The packaged programs.
dpkg-deb -x "$deb" "$work/root"
for program in usr/sbin/spinewatchd usr/bin/spinewatch; do
  machine=$(aarch64-linux-gnu-objdump -f "$work/root/$program" | awk '/file format/ { print $NF }')
  [ "$machine" = elf64-littleaarch64 ] || fail "$program is $machine, not elf64-littleaarch64"
done
version=$("${emulator[@]}" "$work/root/usr/bin/spinewatch" --version) || fail "spinewatch --version failed under ${emulator[*]}"
echo "spinewatch --version: $version"
[ -n "$version" ] || fail "spinewatch --version printed nothing"
"${emulator[@]}" "$work/root/usr/sbin/spinewatchd" --print-config >"$work/config.out" 2>&1 ||
  fail "spinewatchd --print-config failed: $(cat "$work/config.out")"
grep -qx '\[publish\]' "$work/config.out" || fail "spinewatchd --print-config printed no [publish] table: $(head -20 "$work/config.out")"
"${emulator[@]}" "$work/root/usr/bin/spinewatch" check --config "$work/root/etc/spinewatch/spinewatch.toml" >"$work/check.out" 2>&1 ||
  fail "spinewatch check on the packaged configuration failed: $(cat "$work/check.out")"
echo "the packaged programs run under ${emulator[0]}: --version, --print-config, check --config"
echo "PASS"
