#!/usr/bin/env bash
# Installs mire's dependencies from Debian's packages: what building the `mire` command needs, and
# with --tests also what the test suite, the Python module, the fuzz targets and the style check
# need. Idempotent: quiet and quick when everything is already present.
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config
  libopencv-dev libopencv-contrib-dev libvisp-dev libapriltag-dev
  libeigen3-dev libceres-dev libgtest-dev libcli11-dev libyaml-dev libyaml-cpp-dev libboost-dev
  libpng-dev nlohmann-json3-dev)
if [ "${1:-}" = "--tests" ]; then
  packages+=(python3-yaml python3-mrcal clang clang-format
    pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib libexpat1-dev chromium
    opencv-doc)  # opencv-doc: OpenCV's left*.jpg photos, real data for the calibration tests
fi
missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
