#!/usr/bin/env bash
# Installs the Debian packages mccd needs, only when one is missing (apt-get needs root).
# The Python module (tools/python) is built for Debian's /usr/bin/python3, whose numpy,
# pytest and matplotlib these packages provide.
# With --ci, also what .ci/run's sanitizer, ThreadSanitizer and fuzzing stages need: clang
# with its sanitizer and libFuzzer runtimes, and dpkg-dev (apt-get source, for oneTBB).
set -euo pipefail
pkgs=(cmake g++ make libtbb-dev libeigen3-dev libgtest-dev libgmp-dev nlohmann-json3-dev libcli11-dev libstb-dev gnuplot-nox libopenmpi-dev openmpi-bin
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib)
if [ "${1:-}" = "--ci" ]; then
  pkgs+=(clang libclang-rt-dev dpkg-dev xz-utils)
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
fi
