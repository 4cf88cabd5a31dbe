#!/usr/bin/env bash
# Builds and runs the libFuzzer target of the scene reader with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer: the reader, validator, writer and resource estimate (scene/) are compiled
# instrumented; the render_mesh library (export formats) is linked from an existing build.
#
#   scripts/fuzz_scene_reader.sh [SECONDS] [BUILD_DIR]     (defaults: 600 s, build)
#
# Objects are kept in BUILD_DIR/fuzz/obj and rebuilt when their source file is newer; after changing a
# header, remove that folder.
#
# The corpus starts from scenes/*.json and grows in BUILD_DIR/fuzz/corpus; crashes are written to
# BUILD_DIR/fuzz/ as crash-* files. The suite runs a short, deterministic version of the same target
# (tests/robust/scene_reader_mutation_test.cpp).
set -euo pipefail
seconds=${1:-600}
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${2:-$root/build}" && pwd)
out="$build/fuzz"
mkdir -p "$out/corpus"
cp "$root"/scenes/*.json "$out/corpus/"
sources=(core/format.cpp scene/strict_json.cpp scene/json_read.cpp scene/json_write.cpp scene/field_checks.cpp scene/range.cpp
         scene/validate.cpp scene/quality.cpp scene/estimate.cpp scene/mesh_import.cpp scene/export_format.cpp
         tests/robust/fuzz/scene_reader_target.cpp tests/robust/fuzz/scene_reader_fuzz.cpp)
cd "$root"
flags=(-std=c++17 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined)
mkdir -p "$out/obj"
objects=()
for src in "${sources[@]}" "$build/generated/scene/default_scene.cpp"; do
  obj="$out/obj/$(echo "$src" | tr '/' '_').o"
  if [[ ! -f "$obj" || "$src" -nt "$obj" ]]; then
    echo "compiling $src"
    clang++ "${flags[@]}" -I"$root" -I"$root/tests/robust" -I"$build/generated" -I/usr/include/eigen3 -c "$src" -o "$obj"
  fi
  objects+=("$obj")
done
clang++ "${flags[@]}" "${objects[@]}" -L"$build/render_mesh" -lshellfrac_render_mesh -lassimp \
  -Wl,-rpath,"$build/render_mesh:$build/core" -o "$out/scene_reader_fuzz"
cd "$out"
# -rss_limit_mb: the target must never allocate much (the estimate refuses large scenes before anything).
./scene_reader_fuzz -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=1024 -timeout=10 \
  -print_final_stats=1 corpus
