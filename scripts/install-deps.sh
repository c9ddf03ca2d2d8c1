#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs MorphMill's build and test dependencies from Debian's packages. Idempotent: installs
# only what is missing, and runs apt-get update only when something is.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libtbb-dev
  libopenvdb-dev libboost-dev libboost-iostreams-dev libblosc-dev zlib1g-dev
  libembree-dev
  libopenmesh-dev
  libcgal-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  chromium
  libplplot-dev plplot-driver-cairo
  libpolyclipping-dev
  pybind11-dev python3-dev python3-numpy
  libssl-dev libcairo2-dev libjs-three
)
# Optional extras for reports and browser checks are added by callers via MORPHMILL_EXTRA_PACKAGES.
if [[ -n "${MORPHMILL_EXTRA_PACKAGES:-}" ]]; then
  read -r -a extra <<< "${MORPHMILL_EXTRA_PACKAGES}"
  packages+=("${extra[@]}")
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
