#include "sim/json_reader.hpp"

#include <cmath>
#include <sstream>

namespace shellfrac::sim {

namespace {
std::string fmt(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}
}  // namespace

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  const bool lo_ok = lo_open ? v > lo : v >= lo;
  const bool hi_ok = hi_open ? v < hi : v <= hi;
  return lo_ok && hi_ok;
}

std::string Range::describe() const {
  const bool no_lo = lo <= -1e307, no_hi = hi >= 1e307;
  if (no_lo && no_hi) return "a finite number";
  if (no_hi) return std::string(lo_open ? "> " : ">= ") + fmt(lo);
  if (no_lo) return std::string(hi_open ? "< " : "<= ") + fmt(hi);
  return std::string("in ") + (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + (hi_open ? ")" : "]");
}

std::string json_type_name(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::object: return "object";
    case Json::value_t::array: return "array";
    case Json::value_t::string: return "string";
    case Json::value_t::boolean: return "boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned: return "integer";
    case Json::value_t::number_float: return "number";
    default: return "unknown";
  }
}

ObjectReader::ObjectReader(const Json& j, std::string path, const std::string& file)
    : json_(&j), path_(std::move(path)), file_(file) {
  if (!j.is_object())
    throw SceneError(file_, path_.empty() ? "/" : path_,
                     "expected an object, got " + json_type_name(j));
}

bool ObjectReader::has(const std::string& key) const {
  known_.insert(key);
  return json_->contains(key);
}

void ObjectReader::fail(const std::string& key, const std::string& message) const {
  throw SceneError(file_, child_path(key), message);
}

void ObjectReader::fail_here(const std::string& message) const {
  throw SceneError(file_, path_.empty() ? "/" : path_, message);
}

const Json& ObjectReader::require(const std::string& key) {
  known_.insert(key);
  auto it = json_->find(key);
  if (it == json_->end()) fail(key, "required key is missing");
  return *it;
}

const Json& ObjectReader::raw(const std::string& key) { return require(key); }

double ObjectReader::to_number(const Json& v, const std::string& path, const Range& r) const {
  if (!v.is_number())
    throw SceneError(file_, path, "expected a number, got " + json_type_name(v));
  const double x = v.get<double>();
  if (!r.contains(x))
    throw SceneError(file_, path, "value " + fmt(x) + " is out of range: must be " + r.describe());
  return x;
}

double ObjectReader::number(const std::string& key, const Range& r) {
  return to_number(require(key), child_path(key), r);
}

double ObjectReader::number_or(const std::string& key, double fallback, const Range& r) {
  return has(key) ? number(key, r) : fallback;
}

int ObjectReader::integer(const std::string& key, const Range& r) {
  const Json& v = require(key);
  if (!v.is_number_integer())
    fail(key, "expected an integer, got " + json_type_name(v) +
                  (v.is_number() ? " " + fmt(v.get<double>()) : ""));
  const double x = v.get<double>();
  if (!r.contains(x)) fail(key, "value " + fmt(x) + " is out of range: must be " + r.describe());
  return v.get<int>();
}

int ObjectReader::integer_or(const std::string& key, int fallback, const Range& r) {
  return has(key) ? integer(key, r) : fallback;
}

bool ObjectReader::boolean_or(const std::string& key, bool fallback) {
  if (!has(key)) return fallback;
  const Json& v = require(key);
  if (!v.is_boolean()) fail(key, "expected true or false, got " + json_type_name(v));
  return v.get<bool>();
}

std::string ObjectReader::string(const std::string& key) {
  const Json& v = require(key);
  if (!v.is_string()) fail(key, "expected a string, got " + json_type_name(v));
  return v.get<std::string>();
}

std::string ObjectReader::string_or(const std::string& key, const std::string& fallback) {
  return has(key) ? string(key) : fallback;
}

std::string ObjectReader::choice(const std::string& key, const std::vector<std::string>& allowed) {
  std::string s = string(key);
  for (const auto& a : allowed)
    if (a == s) return s;
  std::string list;
  for (size_t i = 0; i < allowed.size(); ++i) list += (i ? ", \"" : "\"") + allowed[i] + "\"";
  fail(key, "unknown value \"" + s + "\": allowed are " + list);
}

std::string ObjectReader::choice_or(const std::string& key, const std::string& fallback,
                                    const std::vector<std::string>& allowed) {
  return has(key) ? choice(key, allowed) : fallback;
}

std::vector<double> ObjectReader::numbers(const std::string& key, size_t length, const Range& r) {
  const Json& v = require(key);
  if (!v.is_array() || v.size() != length)
    fail(key, "expected an array of " + std::to_string(length) + " numbers, got " +
                  (v.is_array() ? "an array of " + std::to_string(v.size()) : json_type_name(v)));
  std::vector<double> out;
  for (size_t i = 0; i < length; ++i)
    out.push_back(to_number(v[i], child_path(key) + "/" + std::to_string(i), r));
  return out;
}

std::vector<double> ObjectReader::numbers_or(const std::string& key, std::vector<double> fallback,
                                             const Range& r) {
  return has(key) ? numbers(key, fallback.size(), r) : fallback;
}

std::vector<double> ObjectReader::number_list(const std::string& key, size_t min_length,
                                              const Range& r) {
  const Json& v = array(key, min_length);
  std::vector<double> out;
  for (size_t i = 0; i < v.size(); ++i)
    out.push_back(to_number(v[i], child_path(key) + "/" + std::to_string(i), r));
  return out;
}

std::vector<int> ObjectReader::integers(const std::string& key, size_t length, const Range& r) {
  const Json& v = require(key);
  if (!v.is_array() || v.size() != length)
    fail(key, "expected an array of " + std::to_string(length) + " integers, got " +
                  (v.is_array() ? "an array of " + std::to_string(v.size()) : json_type_name(v)));
  std::vector<int> out;
  for (size_t i = 0; i < length; ++i) {
    const std::string p = child_path(key) + "/" + std::to_string(i);
    if (!v[i].is_number_integer())
      throw SceneError(file_, p, "expected an integer, got " + json_type_name(v[i]));
    const double x = v[i].get<double>();
    if (!r.contains(x))
      throw SceneError(file_, p, "value " + fmt(x) + " is out of range: must be " + r.describe());
    out.push_back(v[i].get<int>());
  }
  return out;
}

std::vector<int> ObjectReader::integers_or(const std::string& key, std::vector<int> fallback,
                                           const Range& r) {
  return has(key) ? integers(key, fallback.size(), r) : fallback;
}

ObjectReader ObjectReader::object(const std::string& key) {
  return ObjectReader(require(key), child_path(key), file_);
}

std::optional<ObjectReader> ObjectReader::optional_object(const std::string& key) {
  if (!has(key)) return std::nullopt;
  return object(key);
}

const Json& ObjectReader::array(const std::string& key, size_t min_length) {
  const Json& v = require(key);
  if (!v.is_array()) fail(key, "expected an array, got " + json_type_name(v));
  if (v.size() < min_length)
    fail(key, "expected at least " + std::to_string(min_length) + " elements, got " +
                  std::to_string(v.size()));
  return v;
}

void ObjectReader::finish() const {
  for (auto it = json_->begin(); it != json_->end(); ++it) {
    if (known_.count(it.key())) continue;
    std::string list;
    for (const auto& k : known_) list += (list.empty() ? "" : ", ") + k;
    throw SceneError(file_, child_path(it.key()),
                     "unknown key \"" + it.key() + "\": allowed here are " + list);
  }
}

}  // namespace shellfrac::sim
