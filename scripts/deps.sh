#!/usr/bin/env bash
# Installs the Debian 12 packages Expanse needs when run as root; otherwise prints the one
# apt-get line and fails. Sourced by demo.sh and test.sh. (Node.js, for the delaunator peer in
# the benchmarks, is optional: the benchmarks skip that peer without it.)
packages=(cmake ninja-build g++ pkg-config git
          libgmp-dev libpng-dev libcli11-dev nlohmann-json3-dev
          libvulkan-dev mesa-vulkan-drivers glslang-tools vulkan-validationlayers
          libcgal-dev catch2 libqhull-dev python3 python3-matplotlib)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [ "$(id -u)" -eq 0 ]; then
    echo "expanse: installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  else
    echo "expanse: missing Debian packages. Run as root:"
    echo "  apt-get install -y ${missing[*]}"
    exit 1
  fi
fi
