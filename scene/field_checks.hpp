#pragma once
// The checks shared by the JSON reader and the validator of scene values (scene/describe.hpp): one place
// for every message, so that a scene built in C++ is refused with exactly the words and JSON pointer a
// scene file would get.
#include <string>
#include <vector>

#include "scene/range.hpp"
#include "scene/scene.hpp"

namespace shellfrac::scene {

inline const char* const kPointMessage = "expected a parameter point [u, v] of two finite numbers";

inline constexpr std::size_t kMaxTextBytes = 4096;

bool is_quality(const std::string& value);

class FieldChecks {
 public:
  FieldChecks(std::string file, std::string path) : file_(std::move(file)), path_(std::move(path)) {}

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  // JSON pointer of a key of this object; "" names the object itself.
  std::string child(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  void number(const std::string& key, double x, const Range& r) const;
  void choice(const std::string& key, const std::string& value, const std::vector<std::string>& allowed) const;
  void point_count(const std::string& key, size_t count, size_t min_count) const;
  void element_count(const std::string& key, size_t count, size_t min_count) const;
  void point2(const std::string& key, const Vec2& p) const;  // both coordinates finite
  void point3(const std::string& key, const Vec3& p) const;  // each coordinate finite (error at key/d)
  // Names and file paths: no control characters (a newline in a name would break every text format the
  // name is written into) and at most kMaxTextBytes bytes.
  void text(const std::string& key, const std::string& value) const;

 private:
  std::string file_, path_;
};

}  // namespace shellfrac::scene
