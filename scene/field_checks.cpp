#include "scene/field_checks.hpp"

#include <cmath>
#include <cstdio>

#include "scene/scene_error.hpp"

namespace shellfrac::scene {

bool is_quality(const std::string& value) { return value == "draft" || value == "default" || value == "high"; }

std::string FieldChecks::child(const std::string& key) const {
  if (key.empty()) return path_.empty() ? "/" : path_;
  return path_ + "/" + key;
}

void FieldChecks::fail(const std::string& key, const std::string& message) const {
  throw SceneError(file_, child(key), message);
}

void FieldChecks::number(const std::string& key, double x, const Range& r) const {
  if (!r.contains(x)) fail(key, r.violation(x));
}

void FieldChecks::choice(const std::string& key, const std::string& value, const std::vector<std::string>& allowed) const {
  for (const auto& a : allowed)
    if (a == value) return;
  std::string list;
  for (size_t i = 0; i < allowed.size(); ++i) list += (i ? ", \"" : "\"") + allowed[i] + "\"";
  fail(key, "unknown value \"" + value + "\": allowed are " + list);
}

void FieldChecks::point_count(const std::string& key, size_t count, size_t min_count) const {
  if (count < min_count)
    fail(key, "expected at least " + std::to_string(min_count) + " points [u, v], got " + std::to_string(count));
}

void FieldChecks::element_count(const std::string& key, size_t count, size_t min_count) const {
  if (count < min_count)
    fail(key, "expected at least " + std::to_string(min_count) + " elements, got " + std::to_string(count));
}

void FieldChecks::point2(const std::string& key, const Vec2& p) const {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1])) fail(key, kPointMessage);
}

void FieldChecks::point3(const std::string& key, const Vec3& p) const {
  for (size_t d = 0; d < 3; ++d)
    if (!std::isfinite(p[d])) fail(key + "/" + std::to_string(d), "expected a finite number");
}

void FieldChecks::text(const std::string& key, const std::string& value) const {
  if (value.size() > kMaxTextBytes)
    fail(key, "text of " + std::to_string(value.size()) + " bytes is longer than the limit of " +
                  std::to_string(kMaxTextBytes));
  for (size_t i = 0; i < value.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(value[i]);
    if (c < 0x20 || c == 0x7f) {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02x", c);
      fail(key, "contains the control character " + std::string(code) + " at byte " + std::to_string(i) +
                    " (names and paths must be printable text)");
    }
  }
}

}  // namespace shellfrac::scene
