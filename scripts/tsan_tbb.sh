#!/usr/bin/env bash
# Builds oneTBB with ThreadSanitizer into build/tsan-tbb/prefix, for the preset tsan.
#
# Why: ThreadSanitizer sees only the synchronisation of instrumented code. Debian's libtbb is not
# instrumented, so the hand-off of every TBB task (spawn, steal, wait) is invisible to it and it
# reports each write before a parallel_for and each read inside one as a data race: ~100,000 false
# reports on our test suite, on our own data, which no suppression could tell from a real race. With
# TBB itself built with -fsanitize=thread those reports vanish and a report is a real one.
#
# The source is Debian's own (`apt-get source`, the same version as the installed libtbb-dev, through
# a private apt list folder: the system's apt configuration is not touched). The headers installed
# with it are that same version, so arbor compiles against them exactly as against the system's.
# Skipped when the prefix already holds that version. Only libtbb is built: with libhwloc-dev on the
# machine (Open MPI brings it) oneTBB would also configure tbbbind, which the install then misses.
set -euo pipefail
cd "$(dirname "$0")/.."
out=build/tsan-tbb
prefix=$out/prefix
version=$(dpkg-query -W -f='${Version}' libtbb-dev)
if [ -f "$prefix/VERSION" ] && [ "$(cat "$prefix/VERSION")" = "$version" ]; then
  echo "tsan_tbb: oneTBB $version with ThreadSanitizer already in $prefix"
  exit 0
fi
rm -rf "$out"
mkdir -p "$out/apt/lists/partial" "$out/apt/cache/archives/partial" "$out/src"
apt_dir=$(cd "$out/apt" && pwd)
. /etc/os-release
cat >"$apt_dir/sources.list" <<EOF
deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian $VERSION_CODENAME main
deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian $VERSION_CODENAME-updates main
deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian-security $VERSION_CODENAME-security main
EOF
apt_opts=(-q -o "Dir::Etc::SourceList=$apt_dir/sources.list" -o Dir::Etc::SourceParts=/dev/null
          -o "Dir::State::Lists=$apt_dir/lists" -o "Dir::Cache=$apt_dir/cache")
# As root apt would download as the user _apt, who cannot write to this folder (and says so).
[ "$(id -u)" -eq 0 ] && apt_opts+=(-o APT::Sandbox::User=root)
fetch() {
  apt-get "${apt_opts[@]}" update >/dev/null &&
    (cd "$out/src" && apt-get "${apt_opts[@]}" source "onetbb=$version" >/dev/null)
}
fetch || { echo "tsan_tbb: fetching the onetbb source failed, trying once more" >&2; sleep 10; fetch; }
src=$(find "$out/src" -mindepth 1 -maxdepth 1 -type d -name 'onetbb-*' | head -1)
cmake -S "$src" -B "$out/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_INSTALL_PREFIX="$(pwd)/$prefix" \
  -DCMAKE_INSTALL_LIBDIR=lib -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBBMALLOC_BUILD=OFF \
  -DTBB_STRICT=OFF -DTBB_DISABLE_HWLOC_AUTOMATIC_SEARCH=ON >/dev/null
cmake --build "$out/build" -j "$(nproc)" --target tbb >/dev/null
cmake --install "$out/build" >/dev/null
echo "$version" >"$prefix/VERSION"
rm -rf "$out/apt" "$out/src" "$out/build"
echo "tsan_tbb: built oneTBB $version with ThreadSanitizer into $prefix"
