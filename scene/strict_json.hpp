#pragma once
// Reading scene text before the format's own checks: the file is read with a
// size cap (so /dev/zero or a runaway generator cannot fill memory), and the JSON is parsed event by event
// so that what nlohmann's DOM parser lets through is refused with the JSON pointer, line and column:
// duplicate keys (nlohmann keeps the last one silently), numbers too large for a double (1e999), and
// nesting deeper than any scene needs.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace shellfrac::scene {

// Largest scene file read: 64 MiB (an explicit control net of a million points takes about 40 MB).
inline constexpr std::size_t kMaxSceneFileBytes = std::size_t{64} << 20;
// Deepest nesting of objects and arrays accepted; a scene needs 8 (shells/0/material/fracture/regions/0/polygon/0).
inline constexpr int kMaxJsonDepth = 64;

// Reads at most max_bytes of a scene file. Throws SceneError (file, no JSON path) when the file cannot be
// opened, is a directory or larger than max_bytes, or a read fails.
std::string read_scene_file(const std::string& path, std::size_t max_bytes = kMaxSceneFileBytes);

// Parses JSON text. Throws SceneError naming `source`, the JSON pointer of the offending value and its
// line and column for a syntax error, a duplicate key (the second one), a number that overflows a double,
// or nesting deeper than kMaxJsonDepth.
nlohmann::json parse_json_strictly(const std::string& text, const std::string& source);

// "line L, column C" (1-based) of a byte offset in text.
std::string line_and_column(const std::string& text, std::size_t offset);

}  // namespace shellfrac::scene
