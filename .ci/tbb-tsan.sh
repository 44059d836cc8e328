#!/usr/bin/env bash
# Builds oneTBB with ThreadSanitizer from Debian's own source package, the same version as the
# installed libtbb-dev, once per machine, and prints the install prefix (stdout's last line).
#
# The system libtbb.so is not instrumented: TSan then sees neither TBB's own synchronisation
# nor its task hand-offs, and reports every access a worker makes after the main thread as a
# race. Built from source with -fsanitize=thread, TBB's atomics and locks are visible to TSan.
#
# Cache: $MCCD_TBB_TSAN_CACHE, else /var/cache/mccd-tbb-tsan (root) or ~/.cache/mccd-tbb-tsan;
# one prefix per TBB version and compiler. Needs apt (adds a deb-src entry for the suites of
# /etc/apt/sources.list.d/debian.sources or /etc/apt/sources.list when none is there yet).
set -euo pipefail
CC=${CC:-clang}
CXX=${CXX:-clang++}
if [ -n "${MCCD_TBB_TSAN_CACHE:-}" ]; then cache=$MCCD_TBB_TSAN_CACHE
elif [ "$(id -u)" -eq 0 ]; then cache=/var/cache/mccd-tbb-tsan
else cache=${XDG_CACHE_HOME:-$HOME/.cache}/mccd-tbb-tsan
fi
version=$(dpkg-query -W -f='${Version}' libtbb-dev)
cxx_id=$("$CXX" --version | head -1 | tr -c 'A-Za-z0-9.\n' '_')
prefix=$cache/${version//[^A-Za-z0-9.]/_}-$cxx_id
if [ -f "$prefix/.complete" ]; then
  echo "$prefix"
  exit 0
fi
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"

# deb-src for the same suites as the binary packages
if ! grep -rqs '^\(Types:.*deb-src\|deb-src \)' /etc/apt/sources.list /etc/apt/sources.list.d/; then
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    sed 's/^Types: deb$/Types: deb-src/' /etc/apt/sources.list.d/debian.sources |
      $SUDO tee /etc/apt/sources.list.d/mccd-deb-src.sources >/dev/null
  else
    grep '^deb ' /etc/apt/sources.list | sed 's/^deb /deb-src /' |
      $SUDO tee /etc/apt/sources.list.d/mccd-deb-src.list >/dev/null
  fi
  $SUDO apt-get update -qq >&2
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/mccd-tbb-tsan.XXXXXX")
trap 'rm -rf "$work"' EXIT
(cd "$work" && apt-get source -qq --download-only "onetbb=$version" >&2 &&
  dpkg-source --no-check -x ./*.dsc src >/dev/null)
cmake -S "$work/src" -B "$work/build" -G "Unix Makefiles" \
  -DCMAKE_C_COMPILER="$CC" -DCMAKE_CXX_COMPILER="$CXX" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTBB_SANITIZE=thread -DTBB_TEST=OFF -DTBB_EXAMPLES=OFF -DTBB_STRICT=OFF -DTBBMALLOC_BUILD=OFF \
  -DTBB_DISABLE_HWLOC_AUTOMATIC_SEARCH=ON -DCMAKE_INSTALL_PREFIX="$prefix.tmp" >&2
cmake --build "$work/build" -j"$(nproc)" >&2
rm -rf "$prefix.tmp"
cmake --install "$work/build" >&2
# Atomic publication: a half-built prefix is never taken for a finished one.
rm -rf "$prefix"
mv "$prefix.tmp" "$prefix"
touch "$prefix/.complete"
echo "$prefix"
