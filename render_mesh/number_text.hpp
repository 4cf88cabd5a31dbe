#pragma once
// Locale-independent number text for the mesh writers (printf would follow LC_NUMERIC).
#include <charconv>
#include <string>

namespace shellfrac::render_mesh::detail {

// `value` with `digits` significant digits, shortest form ("0.5", "1e-05"); 9 digits restore a float
// exactly, 17 a double.
inline void append_number(std::string& out, double value, int digits) {
  char buffer[40];
  const auto r = std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general, digits);
  out.append(buffer, r.ptr);
}

// The shortest text that reads back as exactly this float.
inline void append_float(std::string& out, float value) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, r.ptr);
}

inline void append_integer(std::string& out, long long value) {
  char buffer[24];
  const auto r = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, r.ptr);
}

}  // namespace shellfrac::render_mesh::detail
