#!/usr/bin/env bash
# Install (or with --check, verify) the Debian packages rebond builds and runs with.
set -euo pipefail
PKGS=(gfortran gcc make libsuitesparse-dev libarpack2-dev liblapack-dev libblas-dev libopenblas0-pthread libhdf5-dev python3 python3-numpy python3-matplotlib python3-h5py python3-scipy libopenmpi-dev openmpi-bin libmumps-ptscotch-dev valgrind)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
if [ "${1:-}" = "--check" ]; then echo "missing packages: ${missing[*]}"; exit 1; fi
echo "installing: ${missing[*]}"
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
