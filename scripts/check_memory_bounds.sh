#!/usr/bin/env bash
# Runs the extreme accepted inputs under a virtual-memory limit (ulimit -v) and checks each ends
# cleanly: a result (exit 0) or a refusal (exit 2 naming the input), never a crash, a signal or an
# uncaught std::bad_alloc (docs/hardening.md, "Memory bounds under ulimit -v"). Below the bound,
# the largest frame is a clean "out of memory" (exit 1). ctest memory_bounds runs it.
#   LIMIT_MB (default 2048): the documented bound; PATLAB (default build/patlab).
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
patlab=$(realpath "${PATLAB:-build/patlab}")
limit_kb=$((${LIMIT_MB:-2048} * 1024))
work=$(mktemp -d /tmp/patlab-memory.XXXXXX)
trap 'rm -rf "$work"' EXIT
golden=$PWD/tests/data/golden
failures=0

# expect NAME LIMIT_KB EXIT MESSAGE_PART -- ARGS...: runs patlab ARGS under ulimit -v LIMIT_KB.
expect() {
  local name=$1 limit=$2 code=$3 part=$4
  shift 5
  local start=$SECONDS
  (ulimit -v "$limit" && exec "$patlab" "$@") >"$work/$name.out" 2>"$work/$name.err"
  local got=$?
  if [[ $got -ne $code ]] || { [[ -n $part ]] && ! grep -qF -- "$part" "$work/$name.err"; } ||
    grep -qE "internal error|terminate called|Sanitizer" "$work/$name.err"; then
    echo "FAIL $name: exit $got (expected $code with '$part'): $(head -c 400 "$work/$name.err")"
    failures=$((failures + 1))
  else
    echo "ok   $name: exit $got under ulimit -v $((limit / 1024)) MB ($((SECONDS - start)) s)"
  fi
}

# The largest accepted frame: 16384 x 16384 = 2^28 pixels (the pixel budget), all black, and a
# calibration of that size; a PNG header claiming 100000 x 100000.
/usr/bin/python3 - "$work" <<'EOF'
import struct, sys, zlib
work = sys.argv[1]
def png(w, h, rows):
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", rows) + chunk(b"IEND", b"")
c = zlib.compressobj(9)
row = bytes(1 + 16384 * 3)
data = b"".join(c.compress(row) for _ in range(16384)) + c.flush()
open(f"{work}/largest.png", "wb").write(png(16384, 16384, data))
open(f"{work}/claims.png", "wb").write(png(100000, 100000, zlib.compress(b"\0" * 64)))
EOF
sed 's/^image_size_px = .*/image_size_px = [16384, 16384]/' \
  "$golden/ssl-frame.calibration.toml" >"$work/largest.calibration.toml"
cat >"$work/blocks.toml" <<EOF
name = "blocks"
patterns_dir = "$PWD/patterns"
patterns = ["butterfly"]
estimators = ["fast"]
trials = 1500000
seed = 1
[sigma]
values = [1]
EOF

# More trials than a block (2^20): memory is flat beyond it.
expect simulate_beyond_a_block "$limit_kb" 0 "" -- simulate "$work/blocks.toml" -q -j 2 \
  --out "$work/sim"
# The largest frame the budget accepts is decoded and segmented.
expect detect_largest_frame "$limit_kb" 0 "" -- detect "$work/largest.png" -q \
  -t "$golden/ssl-frame.thresholds.toml" -c "$work/largest.calibration.toml" --out "$work/det"
# A header beyond the budget is refused before any pixel memory.
expect detect_header_beyond_budget "$limit_kb" 2 "image size 100000x100000; expected 1 to" -- \
  detect "$work/claims.png" -q -t "$golden/ssl-frame.thresholds.toml" \
  -c "$golden/ssl-frame.calibration.toml" --out "$work/claims"
# Below the bound the largest frame cannot be held: a clean exit 1, not a crash.
expect detect_largest_frame_below_the_bound $((512 * 1024)) 1 "out of memory" -- detect \
  "$work/largest.png" -q -t "$golden/ssl-frame.thresholds.toml" \
  -c "$work/largest.calibration.toml" --out "$work/det-small"

if [[ $failures -gt 0 ]]; then
  echo "check_memory_bounds: $failures failures"
  exit 1
fi
echo "check_memory_bounds: every extreme input ended cleanly under ulimit -v"
