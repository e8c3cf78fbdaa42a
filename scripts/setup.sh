#!/usr/bin/env bash
# Installs what sdfvj needs from Debian's packages, if anything is missing. Safe to re-run.
# The JACK trap: jackd2 and libjack-jackd2-dev must be in the same apt line as librtmidi-dev,
# or apt swaps the JACK client library and RtMidi's virtual ports segfault without a server.
set -euo pipefail
PACKAGES=(build-essential cmake pkg-config
  librtmidi-dev liblo-dev liblo-tools libglfw3-dev libglm-dev libimgui-dev catch2 libepoxy-dev
  libegl-dev libegl-mesa0 libgl1-mesa-dri libgles-dev mesa-utils xvfb xauth xfonts-base libxtst-dev
  jackd2 libjack-jackd2-dev libaubio-dev libfftw3-dev
  libtomlplusplus-dev nlohmann-json3-dev libstb-dev libcli11-dev libmuparser-dev ffmpeg parallel python3
  clang-14 libclang-rt-14-dev
  libvulkan-dev mesa-vulkan-drivers glslang-tools glslang-dev)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO apt-get update -qq
echo "jackd2 jackd2/tweak-rt-limits boolean false" | $SUDO debconf-set-selections
# Always the whole list in one line (see the JACK trap above).
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${PACKAGES[@]}" >/dev/null
