#!/usr/bin/env bash
# Installs every Debian package fdem needs to build, test, run its examples
# and draw its charts. Safe to run again: apt-get skips what is installed.
set -euo pipefail
pkgs=(build-essential cmake pkg-config petsc-dev libopenmpi-dev openmpi-bin
      libmetis-dev libhdf5-openmpi-dev libgtest-dev libyaml-cpp-dev
      python3 python3-matplotlib python3-numpy python3-h5py)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
$SUDO apt-get update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
