#!/usr/bin/env bash
# The rooms' layering and file sizes against scripts/rooms.txt (docs/architecture.md, "The rooms
# and what they may use"): includes, each room's CMakeLists.txt, cycles, the build order, the
# document's table, and no .cpp/.h over 500 lines. Prints each problem as file:line and exits 1.
#   bash scripts/check_layering.sh [--root DIR]
set -euo pipefail
exec /usr/bin/python3 -B "$(dirname "$0")/check_layering.py" "$@"
