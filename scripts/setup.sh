#!/usr/bin/env bash
# Set up a fresh Debian machine for the toolkit: system libraries for gmsh and off-screen
# pyvista, then a virtual environment .venv/ at the repository root with the package installed.
# Idempotent: a second run only checks what is already there.
set -euo pipefail
cd "$(dirname "$0")/.."

system_packages="libglu1-mesa libgl1 libxcursor1 libxft2 libxinerama1 libgomp1 libegl1 libxrender1"
missing=""
for p in $system_packages; do
  dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
if [ -n "$missing" ]; then
  if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
  echo "setup: installing system packages:$missing"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi

if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
.venv/bin/python -m pip install -q -e ".[test]"
