#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sim/scene_error.hpp"

namespace shellfrac::sim {

using Json = nlohmann::json;

// Allowed interval for a number, with the wording used in error messages ("> 0", "in (-1, 0.5)").
struct Range {
  double lo = -1e308, hi = 1e308;
  bool lo_open = false, hi_open = false;

  static Range any() { return {}; }
  static Range positive() { return {0.0, 1e308, true, false}; }
  static Range non_negative() { return {0.0, 1e308, false, false}; }
  static Range at_least(double v) { return {v, 1e308, false, false}; }
  static Range open(double a, double b) { return {a, b, true, true}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range left_open(double a, double b) { return {a, b, true, false}; }

  bool contains(double v) const;
  std::string describe() const;
};

// Reads one JSON object of a scene file and validates it as it goes. Every accessor records the key
// as known; finish() then rejects unknown keys (typos must not be silently ignored). All errors are
// SceneErrors naming the file and the JSON pointer of the value.
class ObjectReader {
 public:
  ObjectReader(const Json& j, std::string path, const std::string& file);

  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  std::string child_path(const std::string& key) const { return path_ + "/" + key; }
  bool has(const std::string& key) const;
  const Json& raw(const std::string& key);  // required, any type

  double number(const std::string& key, const Range& r = Range::any());
  double number_or(const std::string& key, double fallback, const Range& r = Range::any());
  int integer(const std::string& key, const Range& r = Range::any());
  int integer_or(const std::string& key, int fallback, const Range& r = Range::any());
  bool boolean_or(const std::string& key, bool fallback);
  std::string string(const std::string& key);
  std::string string_or(const std::string& key, const std::string& fallback);
  // A string that must be one of `allowed`.
  std::string choice(const std::string& key, const std::vector<std::string>& allowed);
  std::string choice_or(const std::string& key, const std::string& fallback,
                        const std::vector<std::string>& allowed);

  // Fixed-length numeric array, e.g. a 3-vector or an [R, S] pair.
  std::vector<double> numbers(const std::string& key, size_t length, const Range& r = Range::any());
  std::vector<double> numbers_or(const std::string& key, std::vector<double> fallback,
                                 const Range& r = Range::any());
  // Numeric array of any length >= min_length.
  std::vector<double> number_list(const std::string& key, size_t min_length,
                                  const Range& r = Range::any());
  std::vector<int> integers(const std::string& key, size_t length, const Range& r = Range::any());
  std::vector<int> integers_or(const std::string& key, std::vector<int> fallback,
                               const Range& r = Range::any());

  ObjectReader object(const std::string& key);
  std::optional<ObjectReader> optional_object(const std::string& key);
  // The array at key (required; must be an array of at least min_length elements).
  const Json& array(const std::string& key, size_t min_length = 0);

  // Throws if the object holds keys that no accessor asked for.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  [[noreturn]] void fail_here(const std::string& message) const;

 private:
  const Json& require(const std::string& key);
  double to_number(const Json& v, const std::string& path, const Range& r) const;

  const Json* json_;
  std::string path_;
  std::string file_;
  mutable std::set<std::string> known_;
};

// JSON type name for messages ("number", "string", "array", ...).
std::string json_type_name(const Json& v);

}  // namespace shellfrac::sim
