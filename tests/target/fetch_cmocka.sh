#!/usr/bin/env bash
# fetch_cmocka.sh -- Debian's cmocka source package, the version of the host's libcmocka-dev,
# unpacked into .target-deps/cmocka-VERSION/ for the Cortex-M4F unit tests (tests/target/);
# Debian ships cmocka built for the host only. Run by scripts/setup; quick when it is there.
#
#   tests/target/fetch_cmocka.sh          fetch if missing
#   tests/target/fetch_cmocka.sh --dir    print the source directory (relative to the checkout)
#
# A private apt configuration (a deb-src list of the system's suite, its own lists and cache) as
# scripts/lib/uml.sh uses: the system's sources and packages are not touched; apt checks the
# source package against the suite's signed index. Nothing of it enters the repository.
set -u
cd "$(dirname "$0")/../.."
version=$(dpkg-query -W -f='${Version}' libcmocka-dev 2>/dev/null) \
  || { echo "fetch_cmocka: libcmocka-dev is not installed (scripts/setup installs it)" >&2; exit 1; }
dir=.target-deps/cmocka-$version
if [ "${1:-}" = --dir ]; then echo "$dir"; exit 0; fi
[ -f "$dir/src/cmocka.c" ] && exit 0

suite=${CMOCKA_DEBIAN_SUITE:-bookworm} mirror=${CMOCKA_DEBIAN_MIRROR:-http://deb.debian.org/debian}
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
why="fetch_cmocka: cannot fetch Debian's cmocka $version source package from $suite ($mirror)"
tmp=$(mktemp -d "${TMPDIR:-/tmp}/cmocka-source.XXXXXX") || exit 1
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/lists/partial" "$tmp/cache/archives/partial" "$tmp/src"
echo "deb-src [signed-by=$keyring] $mirror $suite main" > "$tmp/sources.list"
apt=(-o "Dir::Etc::sourcelist=$tmp/sources.list" -o Dir::Etc::sourceparts=-
     -o "Dir::State::Lists=$tmp/lists" -o "Dir::Cache=$tmp/cache"
     -o "APT::Sandbox::User=$(id -un)" -o Debug::NoLocking=1 -qq)
apt-get "${apt[@]}" update >"$tmp/log" 2>&1 \
  || { echo "$why: apt-get update: $(grep -m1 -E '^(E|W):' "$tmp/log" || tail -n1 "$tmp/log")" >&2; exit 1; }
(cd "$tmp/src" && apt-get "${apt[@]}" source --download-only "cmocka=$version") >"$tmp/log" 2>&1 \
  || { echo "$why: apt-get source: $(grep -m1 '^E:' "$tmp/log" || tail -n1 "$tmp/log")" >&2; exit 1; }
dpkg-source -x "$tmp"/src/cmocka_*.dsc "$tmp/cmocka" >"$tmp/log" 2>&1 \
  || { echo "$why: dpkg-source: $(tail -n1 "$tmp/log")" >&2; exit 1; }
mkdir -p .target-deps && rm -rf "$dir" && mv "$tmp/cmocka" "$dir" && echo "fetch_cmocka: Debian's cmocka $version source in $dir"
