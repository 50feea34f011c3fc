#!/usr/bin/env bash
# Set up (if needed) and regenerate every validation table in quick mode.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/env.sh
.venv/bin/python -m validation all --quick "$@"
