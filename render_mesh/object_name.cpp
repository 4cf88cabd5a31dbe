#include "render_mesh/object_name.hpp"

#include <cstdint>

namespace shellfrac::render_mesh {

namespace {

constexpr size_t kMaxNameBytes = 255;

// Length of the valid UTF-8 sequence starting at s[i] and its code point, or 0 if it is not valid
// (overlong forms, surrogates and values above U+10FFFF are invalid).
size_t utf8_sequence(const std::string& s, size_t i, std::uint32_t& code) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b0 = byte(i);
  size_t length;
  std::uint32_t min;
  if (b0 < 0x80) {
    code = b0;
    return 1;
  } else if ((b0 & 0xE0) == 0xC0) {
    length = 2, code = b0 & 0x1Fu, min = 0x80;
  } else if ((b0 & 0xF0) == 0xE0) {
    length = 3, code = b0 & 0x0Fu, min = 0x800;
  } else if ((b0 & 0xF8) == 0xF0) {
    length = 4, code = b0 & 0x07u, min = 0x10000;
  } else {
    return 0;
  }
  if (i + length > s.size()) return 0;
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3Fu);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

bool replaced(std::uint32_t c) {
  return c < 0x20 || c == 0x7F || (c >= 0x80 && c <= 0x9F) || c == 0x2028 || c == 0x2029 || c == ' ' ||
         c == '#';
}

std::string sanitise(const std::string& name) {
  std::string out;
  out.reserve(name.size());
  for (size_t i = 0; i < name.size();) {
    std::uint32_t code = 0;
    const size_t n = utf8_sequence(name, i, code);
    const size_t width = n == 0 || replaced(code) ? 1 : n;
    if (out.size() + width > kMaxNameBytes) break;
    if (n == 0 || replaced(code))
      out += '_';
    else
      out.append(name, i, n);
    i += n == 0 ? 1 : n;
  }
  return out;
}

}  // namespace

std::string export_object_name(const std::string& name, const std::string& fallback) {
  std::string out = sanitise(name);
  if (out.empty()) out = sanitise(fallback);
  return out;
}

}  // namespace shellfrac::render_mesh
