#!/usr/bin/env bash
# Installs the Debian packages dhdr builds, tests and benchmarks with. Idempotent: a
# machine that already has them is left alone and apt is never touched.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libopenimageio-dev openimageio-tools libopenexr-dev libimath-dev python3-imath  # python3-imath: ImathTargets.cmake names its library
  libopencolorio-dev libembree-dev libglm-dev libassimp-dev
  nlohmann-json3-dev libgtest-dev python3
  libdeflate-dev  # dhdr-tonemap's PNG writer deflates whole frames with it (libio)
  pngcheck        # an independent PNG checker for test_png_writer
  python3-murmurhash  # an independent MurmurHash3_x86_32 for the Cryptomatte tests
  pybind11-dev python3-dev python3-numpy  # the dhdr Python module (python/)
  python3-pytest python3-openimageio      # its tests: pytest, and an independent EXR reader
  slurm-wlm munge     # the farm tests start a single-node Slurm cluster (tests/farm)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
