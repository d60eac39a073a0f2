# uml.sh -- the User-Mode Linux kernel that scripts/with-vcan boots where the host kernel has no
# CAN support; sourced by scripts/setup (uml_provision) and scripts/with-vcan (uml_dir).
#
# The kernel is Debian's own `user-mode-linux` package, version 7 or later, from the suite that
# carries it (sid; override with UML_DEBIAN_SUITE), unpacked into a directory of the project's
# ($WITH_VCAN_UML_DIR, default .uml/ in the checkout) together with the C library of the same
# suite. The system's apt configuration, libc and packages are not touched:
#   linux.uml   the kernel, its loader and library path set to lib/ (patchelf)
#   lib/        the C library it was built against
#   modules/    its CAN modules (net/can, drivers/net/can), loaded by full path
#   release     the kernel's release (e.g. 7.2.7); packages: the two packages' versions
#   .provisioned-by-fcc-hil   the marker that the directory is setup's to replace
# A directory setup did not provision is never replaced: a non-empty one without the marker
# (or, from before the marker, without the kernel's own three files) is refused before anything
# is downloaded.
# Why not the system's user-mode-linux: bookworm's 6.1 and trixie's 6.12 panic on hosts whose CPU
# has AVX-512 and AMX ("ptrace set fp regs failed"), and where 6.1 boots a system call in its
# guest costs 2.5x what it costs in 7.2 with seccomp (docs: performance).

uml_dir() { echo "${WITH_VCAN_UML_DIR:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/.uml}"; }

# Whether DIR holds a provisioned kernel whose loader is where it was put (a moved checkout is not).
uml_ready() {
  local dir=$1
  [ -x "$dir/linux.uml" ] && [ -s "$dir/release" ] && [ -x "$dir/lib/ld-linux-x86-64.so.2" ] \
    && [ "$(patchelf --print-interpreter "$dir/linux.uml" 2>/dev/null)" = "$dir/lib/ld-linux-x86-64.so.2" ]
}

UML_MARKER=.provisioned-by-fcc-hil

# Whether DIR may be replaced by a provisioned kernel: absent, empty, or one setup provisioned
# (its marker, or a kernel directory from before the marker: linux.uml, release and the loader).
# Otherwise print one line on stderr (prefixed with the caller's $prog) and return 1.
uml_ours() {
  local dir=$1
  if [ ! -e "$dir" ] && [ ! -L "$dir" ]; then return 0; fi
  if [ -d "$dir" ]; then
    [ -z "$(ls -A "$dir")" ] || [ -f "$dir/$UML_MARKER" ] && return 0
    [ -f "$dir/linux.uml" ] && [ -f "$dir/release" ] && [ -f "$dir/lib/ld-linux-x86-64.so.2" ] && return 0
  fi
  echo "${prog:-uml}: refusing to put the User-Mode Linux kernel into $dir: it is not empty and was not provisioned by setup (no $UML_MARKER); name a new or empty directory in WITH_VCAN_UML_DIR" >&2
  return 1
}

# Download and unpack the kernel into DIR; on failure print one line on stderr and return 1.
# DIR is replaced only when uml_ours allows it, checked before anything is downloaded.
uml_provision() {
  local dir=$1 suite=${UML_DEBIAN_SUITE:-sid} mirror=${UML_DEBIAN_MIRROR:-http://deb.debian.org/debian}
  local keyring=/usr/share/keyrings/debian-archive-keyring.gpg
  uml_ours "$dir" || return 1
  local why="cannot provision User-Mode Linux >= 7 from Debian $suite ($mirror)"
  local fix="set UML_DEBIAN_MIRROR to a reachable Debian mirror, or run on a kernel with vcan (modprobe vcan)"
  [ -r "$keyring" ] || { echo "$why: $keyring is missing (install debian-archive-keyring)" >&2; return 1; }
  command -v patchelf >/dev/null || { echo "$why: patchelf is missing (apt-get install patchelf)" >&2; return 1; }
  local tmp; tmp=$(mktemp -d "${TMPDIR:-/tmp}/uml-provision.XXXXXX") || return 1
  mkdir -p "$tmp/lists/partial" "$tmp/cache/archives/partial" "$tmp/debs" "$tmp/root"
  echo "deb [signed-by=$keyring] $mirror $suite main" > "$tmp/sources.list"
  # A private package list: the system's sources, lists and cache stay as they are.
  local apt=(-o "Dir::Etc::sourcelist=$tmp/sources.list" -o Dir::Etc::sourceparts=-
             -o "Dir::State::Lists=$tmp/lists" -o "Dir::Cache=$tmp/cache"
             -o "APT::Sandbox::User=$(id -un)" -o Debug::NoLocking=1 -qq)
  local log=$tmp/apt.log
  if ! apt-get "${apt[@]}" update >"$log" 2>&1; then
    echo "$why: apt-get update failed: $(grep -m1 -E '^(E|W):' "$log" || tail -n1 "$log"); $fix" >&2
    rm -rf "$tmp"; return 1
  fi
  if ! (cd "$tmp/debs" && apt-get "${apt[@]}" download user-mode-linux libc6) >"$log" 2>&1; then
    echo "$why: apt-get download failed: $(grep -m1 '^E:' "$log" || tail -n1 "$log"); $fix" >&2
    rm -rf "$tmp"; return 1
  fi
  local deb version
  for deb in "$tmp"/debs/*.deb; do dpkg-deb -x "$deb" "$tmp/root" || { rm -rf "$tmp"; return 1; }; done
  version=$(dpkg-deb -f "$tmp"/debs/user-mode-linux_*.deb Version)
  if [ "${version%%.*}" -lt 7 ] 2>/dev/null || [ -z "$version" ]; then
    echo "$why: $suite has user-mode-linux '$version', older than 7; set UML_DEBIAN_SUITE" >&2
    rm -rf "$tmp"; return 1
  fi
  local modules; modules=$(echo "$tmp"/root/usr/lib/uml/modules/*/)
  local stage; stage=$(mktemp -d "$dir.new.XXXXXX") || { rm -rf "$tmp"; return 1; }
  mkdir -p "$stage/lib" "$stage/modules/kernel/net" "$stage/modules/kernel/drivers/net"
  cp -a "$tmp"/root/usr/lib/x86_64-linux-gnu/*.so* "$stage/lib/" &&
    cp -a "$modules/kernel/net/can" "$stage/modules/kernel/net/" &&
    cp -a "$modules/kernel/drivers/net/can" "$stage/modules/kernel/drivers/net/" &&
    cp "$tmp/root/usr/bin/linux.uml" "$stage/linux.uml" &&
    basename "$modules" > "$stage/release" &&
    dpkg-deb --showformat='${Package} ${Version}\n' -W "$tmp"/debs/*.deb > "$stage/packages" &&
    touch "$stage/$UML_MARKER" && uml_ours "$dir" && rm -rf "$dir" && mv "$stage" "$dir" &&
    patchelf --set-interpreter "$dir/lib/ld-linux-x86-64.so.2" --set-rpath "$dir/lib" "$dir/linux.uml"
  local status=$?
  rm -rf "$tmp" "$stage"
  [ $status = 0 ] || { echo "$why: cannot install it into $dir" >&2; return 1; }
}
