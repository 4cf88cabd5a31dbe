#!/usr/bin/env bash
# Byte-identical behaviour check for refactors. Runs a fixed set of shipped scenes and records the SHA-256
# of every frame file and of summary.json with its run-dependent fields (timings, paths, version) removed.
#
#   scripts/check-golden.sh record FILE [BINARY]   run the scenes and write their hashes to FILE
#   scripts/check-golden.sh check  FILE [BINARY]   run them again and compare with FILE (exit 1 on any change)
#
# BINARY defaults to build/bin/shellfrac. Runs use 2 threads: output is bit-identical for a given thread
# count. Set GOLDEN_SCENES to override the scene list (paths under scenes/, without .json, such as
# brittle/slab-sphere; "default" is the built-in scene).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-}
file=${2:-}
binary=${3:-build/bin/shellfrac}
if [[ "$mode" != record && "$mode" != check ]] || [[ -z "$file" ]]; then
  sed -n '2,10p' "$0" >&2
  exit 2
fi
[[ -x "$binary" ]] || { echo "check-golden: no executable at $binary (build first)" >&2; exit 2; }
command -v python3 >/dev/null || { echo "check-golden: needs python3 (to strip timings from summary.json)" >&2; exit 2; }

scenes=${GOLDEN_SCENES:-"default tear-mode-one spiral-cut cloth-two-balls garment-eight-patches drape-two-patch-c1 plate-pressure brittle/slab-sphere brittle/notched-beam brittle/statue-strike brittle/shapes-drop brittle/statue-drop"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

hash_run() {  # scene name -> lines "scene file sha256"
  local name=$1 out="$work/$1"
  mkdir -p "$(dirname "$out")"
  local args=(run --out "$out" --threads 2)
  [[ "$name" != default ]] && args=(run "scenes/$name.json" --out "$out" --threads 2)
  if ! "$binary" "${args[@]}" >"$work/$name.log" 2>&1; then
    echo "$name run failed exit=$?"  # a failing run is part of the behaviour too
  fi
  # Shell frames, the shatter loop's rigid frames and animation, the brittle events' files; not the
  # .vdb particle files, whose header holds a random UUID per file.
  local dirs=()
  for d in frames rigid brittle; do [[ -d "$out/$d" ]] && dirs+=("$d"); done
  (cd "$out" && find "${dirs[@]}" -type f ! -name '*.vdb' | LC_ALL=C sort | while read -r f; do
     echo "$name $f $(sha256sum "$f" | cut -d' ' -f1)"; done)
  python3 - "$out/summary.json" <<'PY' | { read -r h; echo "$name summary.json $h"; }
import hashlib, json, sys
drop = {"wall_seconds", "stage_seconds", "scene_source", "shellfrac_version", "threads"}
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items()
                if k not in drop and "per_second" not in k and k != "seconds" and not k.endswith("_seconds")}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v
s = strip(json.load(open(sys.argv[1])))
print(hashlib.sha256(json.dumps(s, sort_keys=True).encode()).hexdigest())
PY
}

result="$work/hashes.txt"
for s in $scenes; do
  echo "check-golden: $s" >&2
  hash_run "$s" >>"$result"
done
if [[ $mode == record ]]; then
  cp "$result" "$file"
  echo "check-golden: recorded $(wc -l <"$file") hashes in $file" >&2
else
  if diff -u "$file" "$result"; then
    echo "check-golden: identical ($(wc -l <"$file") hashes)" >&2
  else
    echo "check-golden: output changed (diff above)" >&2
    exit 1
  fi
fi
