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

# Debian's chromium opens report.html in tests/validation/test_crosscheck_html.py (Playwright
# drives it; a browser download of Playwright's own is not used). Without it that test skips.
if ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi
  echo "setup: installing chromium (the HTML report's browser test)"
  { $SUDO apt-get update -qq \
    && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends chromium >/dev/null; } \
    || echo "setup: chromium could not be installed; the HTML report's browser test will skip"
fi

if [ ! -x .venv/bin/python ]; then
  python3 -m venv .venv
fi
# the package and its test extra, again only when pyproject.toml changed since the last install
stamp=.venv/.installed-pyproject
want="$(sha256sum pyproject.toml | cut -d' ' -f1)"
if [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
  .venv/bin/python -m pip install -q --upgrade pip
  .venv/bin/python -m pip install -q -e ".[test]"
  echo "$want" > "$stamp"
fi
