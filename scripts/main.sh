#!/usr/bin/env bash
# Set up (if needed) and regenerate every validation table in quick mode, into the git-ignored
# validation/results-quick/ (the committed full results in validation/results/ stay untouched).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/env.sh
.venv/bin/python -m validation all --quick "$@"
