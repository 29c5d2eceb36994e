#!/usr/bin/env bash
# Installs the Debian packages setbound needs, only those missing (sudo when not root).
set -euo pipefail
packages=(g++ make cmake ninja-build pkg-config libeigen3-dev libnlopt-dev libnlopt-cxx-dev libgtest-dev ccache libqhull-dev)
# A Python with the venv module is needed too (Debian splits it into python3-venv).
if ! command -v python3 >/dev/null 2>&1; then
  packages+=(python3 python3-venv python3-dev)
elif ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
  packages+=(python3-venv)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
