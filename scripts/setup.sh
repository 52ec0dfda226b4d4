#!/usr/bin/env bash
# Installs every Debian package mcref needs. Idempotent; needs root (or sudo).
set -euo pipefail
PACKAGES=(
  g++ cmake make git pkg-config
  libembree-dev libopenvdb-dev libboost-iostreams-dev libtbb-dev
  libhdf5-dev libtomlplusplus-dev libgtest-dev libbenchmark-dev
  python3-matplotlib python3-h5py python3-numpy python3-jinja2
  python3-xarray python3-h5netcdf python3-openvdb
  chromium
  pybind11-dev python3-pybind11 python3-pytest
  python3-torch
  libopenmpi-dev openmpi-bin
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
