#!/usr/bin/env bash
# The Debian package of this build tree, installed and run:
#  1. cpack packages the build as it is (nothing is compiled; the Ninja
#     build has no preinstall step), into a scratch directory;
#  2. the control fields: name, this machine's architecture, and a Depends
#     that names the package of every shared library spinewatchd and
#     spinewatch load (dpkg-shlibdeps), plus systemd;
#  3. the control archive: the configuration is a conffile, the maintainer
#     scripts are executable shell that parses;
#  4. dpkg installs it into a scratch root (--root, with the maintainer
#     scripts run outside a chroot and told the root in $DPKG_ROOT): the
#     files land where the unit says, the conffile is registered, the
#     postinst created the spinewatch account and the gpio group there (and
#     nothing on this machine); installing it again keeps one account;
#  5. the installed spinewatchd starts on the installed configuration and
#     the installed demo recording, says it is ready, publishes postures the
#     installed CLI reads, and stops with exit 0 on SIGTERM;
#  6. dpkg removes and purges it from the scratch root.
# A chroot or a debootstrap'ed Debian root would also check that apt
# resolves the Depends on a clean system, but needs the network and
# minutes; step 2 checks the same Depends against this machine's packages.
# Usage: deb_install_test.sh BUILD_DIR SOURCE_DIR. Exit 77: cannot run here.
set -euo pipefail

build=$1
src=$2
export PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
export LC_ALL=C

work=$(mktemp -d)
daemon_pid=""
cleanup() {
  if [ -n "$daemon_pid" ]; then kill -KILL "$daemon_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*" >&2
  exit 1
}
skip() {
  echo "SKIP: $*"
  exit 77
}
now_ms() { date +%s%3N; }

for tool in cpack dpkg dpkg-deb objdump ldd systemd-sysusers; do
  command -v "$tool" >/dev/null || skip "$tool is not installed"
done
arch=$(dpkg --print-architecture)

# 1. Package.
t0=$(now_ms)
cpack --config "$build/CPackConfig.cmake" -B "$work/out" >"$work/cpack.log" 2>&1 ||
  fail "cpack failed: $(cat "$work/cpack.log")"
echo "packaged in $(($(now_ms) - t0)) ms"
shopt -s nullglob
debs=("$work"/out/spinewatch_*_"$arch".deb)
[ ${#debs[@]} -eq 1 ] || fail "expected one spinewatch_*_$arch.deb in $work/out, found: $(ls "$work/out")"
deb=${debs[0]}
echo "package: $(basename "$deb"), $(stat -c %s "$deb") bytes"

# 2. Control fields.
field() { dpkg-deb -f "$deb" "$1"; }
[ "$(field Package)" = spinewatch ] || fail "Package: $(field Package)"
[ "$(field Architecture)" = "$arch" ] || fail "Architecture: $(field Architecture), this machine is $arch"
depends=$(field Depends)
echo "Depends: $depends"
depends_names=" $(echo "$depends" | sed -E 's/\([^)]*\)//g; s/[,|]/ /g') "
[[ $depends_names == *" systemd "* ]] || fail "Depends lacks systemd (the maintainer scripts run systemd-sysusers): $depends"
# Every library the two programs load, the file the loader uses (not a
# cross toolchain's of the same name), and the package that owns it; dpkg
# knows a file by its /usr or its merged-/usr name, so both are asked, in
# one query (dpkg -S reads its whole database each time).
declare -A needed_by=()
for binary in "$build/daemon/spinewatchd" "$build/tools/spinewatch"; do
  libraries=$(ldd "$binary")
  for soname in $(objdump -p "$binary" | awk '$1 == "NEEDED" { print $2 }'); do
    path=$(echo "$libraries" | awk -v so="$soname" '$1 == so && $2 == "=>" { print $3 }')
    [ -n "$path" ] || fail "$(basename "$binary") needs $soname, which the loader does not find"
    needed_by[$path]=$(basename "$binary")
  done
done
aliases=()
for path in "${!needed_by[@]}"; do aliases+=("$path" "${path#/usr}" "/usr${path#/usr}"); done
owners=$( (dpkg -S "${aliases[@]}" 2>/dev/null || true) | sed -E 's/^([^:]+)(:[^:]+)?: /\1 /')
for path in "${!needed_by[@]}"; do
  owner=$(echo "$owners" | awk -v a="$path" -v b="${path#/usr}" -v c="/usr${path#/usr}" \
    '$2 == a || $2 == b || $2 == c { print $1; exit }')
  [ -n "$owner" ] || fail "${needed_by[$path]} needs $path, which no installed package provides"
  # The package itself, or a name it provides (shlibs may name one:
  # libspdlog1.10 provides libspdlog1.10-fmt9).
  named=""
  for name in "$owner" $(dpkg-query -W -f='${Provides}' "$owner" | sed -E 's/\([^)]*\)//g; s/,/ /g'); do
    if [[ $depends_names == *" $name "* ]]; then named=$name; fi
  done
  [ -n "$named" ] || fail "${needed_by[$path]} needs $path from $owner, which Depends does not name: $depends"
done
echo "Depends names the packages of all ${#needed_by[@]} libraries the programs load"

# 3. Control archive.
dpkg-deb -e "$deb" "$work/control"
grep -qx /etc/spinewatch/spinewatch.toml "$work/control/conffiles" ||
  fail "conffiles does not list /etc/spinewatch/spinewatch.toml: $(cat "$work/control/conffiles")"
for script in postinst prerm postrm; do
  [ -x "$work/control/$script" ] || fail "$script is missing or not executable"
  sh -n "$work/control/$script" || fail "$script does not parse"
done
grep -q 'systemd-sysusers' "$work/control/postinst" || fail "postinst does not create the accounts"
# What it holds (listed from the archive: a machine's dpkg path-exclude,
# e.g. of /usr/share/doc in container images, would hide it after install).
dpkg-deb -c "$deb" | awk '{ print $6 }' >"$work/contents"
for file in ./usr/sbin/spinewatchd ./usr/bin/spinewatch ./usr/lib/systemd/system/spinewatch.service \
  ./usr/lib/sysusers.d/spinewatch.conf ./etc/spinewatch/spinewatch.toml ./usr/share/spinewatch/demo/recording.json \
  ./usr/share/doc/spinewatch/daemon.md ./usr/share/doc/spinewatch/hardware.md ./usr/share/doc/spinewatch/posture.schema.json; do
  grep -qx "$file" "$work/contents" || fail "the package lacks ${file#.}"
done
# The CLI's media module (video and image files), in the architecture's library directory.
grep -qx "./usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH)/spinewatch/spinewatch-media.so" "$work/contents" ||
  fail "the package lacks the media module (/usr/lib/<arch>/spinewatch/spinewatch-media.so)"

# 4. Install into a scratch root.
root=$work/root
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates" "$root/etc"
touch "$root/var/lib/dpkg/status" "$root/var/lib/dpkg/available"
dpkg_root=(dpkg --root="$root" --force-script-chrootless --force-depends --log=/dev/null)
[ "$(id -u)" -eq 0 ] || dpkg_root+=(--force-not-root)
host_accounts=$(cat /etc/passwd /etc/group)
"${dpkg_root[@]}" -i "$deb" >"$work/dpkg.log" 2>&1 || fail "dpkg -i failed: $(cat "$work/dpkg.log")"
[ "$host_accounts" = "$(cat /etc/passwd /etc/group)" ] || fail "installing into $root changed this machine's accounts"
dpkg-query --admindir="$root/var/lib/dpkg" -W -f='${Status}\n' spinewatch | grep -qx 'install ok installed' ||
  fail "dpkg does not list spinewatch as installed in $root"
dpkg-query --admindir="$root/var/lib/dpkg" -W -f='${Conffiles}\n' spinewatch | grep -q '^ /etc/spinewatch/spinewatch.toml [0-9a-f]\{32\}$' ||
  fail "dpkg did not register the conffile"

for file in usr/sbin/spinewatchd usr/bin/spinewatch usr/lib/systemd/system/spinewatch.service \
  usr/lib/sysusers.d/spinewatch.conf usr/share/spinewatch/demo/recording.json; do
  [ -e "$root/$file" ] || fail "dpkg did not install /$file"
done
# The installed CLI finds its media module beside it: it writes a PNG.
"$root/usr/bin/spinewatch" calibrate --write-board "$work/board.png" --dpi 20 >"$work/board.log" 2>&1 ||
  fail "the installed spinewatch could not write a board image: $(cat "$work/board.log")"
[ -s "$work/board.png" ] || fail "the installed spinewatch wrote no board image"
cmp -s "$root/etc/spinewatch/spinewatch.toml" "$src/config/spinewatch.toml" ||
  fail "/etc/spinewatch/spinewatch.toml is not config/spinewatch.toml"
unit=$root/usr/lib/systemd/system/spinewatch.service
grep -qx 'ExecStart=/usr/sbin/spinewatchd --config /etc/spinewatch/spinewatch.toml' "$unit" ||
  fail "the unit's ExecStart= is not the packaged daemon and conffile: $(grep ExecStart= "$unit")"
grep -qx 'User=spinewatch' "$unit" || fail "the unit does not run as spinewatch"
grep -qx 'SupplementaryGroups=video gpio' "$unit" || fail "the unit's SupplementaryGroups= changed: update the sysusers file"

# The postinst's accounts, in the scratch root only.
grep -q '^spinewatch:x:[0-9]*:[0-9]*:[^:]*:[^:]*:/usr/sbin/nologin$' "$root/etc/passwd" ||
  fail "postinst did not create the system user spinewatch: $(cat "$root/etc/passwd" 2>/dev/null)"
uid=$(awk -F: '$1 == "spinewatch" { print $3 }' "$root/etc/passwd")
[ "$uid" -lt 1000 ] || fail "spinewatch is not a system user (uid $uid)"
grep -q '^spinewatch:x:' "$root/etc/group" || fail "postinst did not create the group spinewatch"
grep -q '^gpio:x:' "$root/etc/group" || fail "postinst did not create the group gpio"
# Again (an upgrade in place): prerm upgrade, postinst configure <version>.
"${dpkg_root[@]}" -i "$deb" >"$work/dpkg.log" 2>&1 || fail "installing again failed: $(cat "$work/dpkg.log")"
[ "$(grep -c '^spinewatch:' "$root/etc/passwd")" -eq 1 ] || fail "installing again duplicated the account"
[ "$(awk -F: '$1 == "spinewatch" { print $3 }' "$root/etc/passwd")" = "$uid" ] || fail "installing again changed the uid"

# 5. The installed daemon on the installed configuration.
for node in /dev/video0 /dev/video1 /dev/video2; do
  [ ! -e "$node" ] || skip "$node exists: cameras.source = \"auto\" would open the cameras, not the embedded default"
done
sock=$work/posture.sock
SPINEWATCH_DATA_DIR=$root/usr/share/spinewatch "$root/usr/sbin/spinewatchd" \
  --config "$root/etc/spinewatch/spinewatch.toml" --listen none --unix "$sock" --http none >"$work/daemon.log" 2>&1 &
daemon_pid=$!
t0=$(now_ms)
until grep -q '; ready$' "$work/daemon.log"; do
  kill -0 "$daemon_pid" 2>/dev/null || fail "spinewatchd exited before it was ready: $(cat "$work/daemon.log")"
  [ $(($(now_ms) - t0)) -lt 60000 ] || fail "spinewatchd not ready within 60 s: $(cat "$work/daemon.log")"
  sleep 0.1
done
echo "ready in $(($(now_ms) - t0)) ms"
grep -qF "running the embedded default: phantom recording $root/usr/share/spinewatch/demo " "$work/daemon.log" ||
  fail "the daemon did not replay the packaged demo recording: $(cat "$work/daemon.log")"
timeout 30 "$root/usr/bin/spinewatch" watch --unix "$sock" --json --count 5 >"$work/postures.ndjson" 2>"$work/watch.log" ||
  fail "the installed CLI read no postures: $(cat "$work/watch.log") / daemon: $(cat "$work/daemon.log")"
postures=$(grep -c '"seq":' "$work/postures.ndjson" || true)
[ "$postures" -ge 5 ] || fail "expected 5 postures, got: $(cat "$work/postures.ndjson")"
echo "read $postures postures through the installed CLI"
kill -TERM "$daemon_pid"
status=0
wait "$daemon_pid" || status=$?
daemon_pid=""
[ "$status" -eq 0 ] || fail "spinewatchd exited $status after SIGTERM: $(cat "$work/daemon.log")"
[ ! -e "$sock" ] || fail "spinewatchd left its socket behind"

# 6. Remove, then purge: the files and the conffile go, the account stays.
"${dpkg_root[@]}" -r spinewatch >"$work/dpkg.log" 2>&1 || fail "dpkg -r failed: $(cat "$work/dpkg.log")"
[ ! -e "$root/usr/sbin/spinewatchd" ] || fail "dpkg -r left the daemon"
[ -e "$root/etc/spinewatch/spinewatch.toml" ] || fail "dpkg -r removed the conffile (only purge may)"
"${dpkg_root[@]}" -P spinewatch >"$work/dpkg.log" 2>&1 || fail "dpkg -P failed: $(cat "$work/dpkg.log")"
[ ! -e "$root/etc/spinewatch" ] || fail "dpkg -P left /etc/spinewatch"
grep -q '^spinewatch:' "$root/etc/passwd" || fail "purging removed the account (its files may outlive it)"
echo "PASS"
