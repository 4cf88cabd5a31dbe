// The JSON reader of the scene format: walks scene/describe.hpp over a parsed document, checking each
// value's type and range as it goes and rejecting keys no declaration asked for.
#include <set>

#include "scene/describe.hpp"
#include "scene/field_checks.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"
#include "scene/strict_json.hpp"

namespace shellfrac::scene {

namespace {

using Json = nlohmann::json;

const Range kIntRange = Range::closed(-2147483648.0, 2147483647.0);

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

class JsonReader {
 public:
  JsonReader(const Json& object, std::string path, const std::string& file) : json_(object), at_(file, std::move(path)) {
    if (!object.is_object()) at_.fail("", "expected an object, got " + json_type_name(object));
  }

  void number(const std::string& key, Opt<double>& x, const Range& r, Need need = kOptional) {
    if (const Json* v = find(key, need)) x = to_number(*v, key, r);
  }
  void integer(const std::string& key, Opt<int>& x, const Range& r, Need need = kOptional) {
    const Json* v = find(key, need);
    if (!v) return;
    if (!v->is_number_integer())
      at_.fail(key, "expected an integer, got " + json_type_name(*v) +
                        (v->is_number() ? " " + format_value(v->get<double>()) : ""));
    at_.number(key, v->get<double>(), r);
    x = v->get<int>();
  }
  void boolean(const std::string& key, Opt<bool>& x, Need need = kOptional) {
    const Json* v = find(key, need);
    if (!v) return;
    if (!v->is_boolean()) at_.fail(key, "expected true or false, got " + json_type_name(*v));
    x = v->get<bool>();
  }
  void string(const std::string& key, Opt<std::string>& x, Need need = kOptional) {
    const Json* v = find(key, need);
    if (!v) return;
    if (!v->is_string()) at_.fail(key, "expected a string, got " + json_type_name(*v));
    x = v->get<std::string>();
    at_.text(key, *x);
  }
  void choice(const std::string& key, Opt<std::string>& x, const std::vector<std::string>& allowed, Need need = kOptional) {
    string(key, x, need);
    if (x) at_.choice(key, *x, allowed);
  }
  void choices(const std::string& key, Opt<std::vector<std::string>>& x, const std::vector<std::string>& allowed,
               size_t min_length, Need need = kOptional) {
    const Json* v = array(key, need, min_length);
    if (!v) return;
    std::vector<std::string> out;
    for (size_t i = 0; i < v->size(); ++i) {
      const std::string element = key + "/" + std::to_string(i);
      if (!(*v)[i].is_string()) at_.fail(element, "expected a string, got " + json_type_name((*v)[i]));
      out.push_back((*v)[i].get<std::string>());
      at_.choice(element, out.back(), allowed);
    }
    x = std::move(out);
  }
  void quality(const std::string& key, Opt<std::string>& x) {
    const Json* v = find(key, kOptional);
    if (!v) return;
    const std::string value = v->is_string() ? v->get<std::string>() : "";
    if (!is_quality(value)) at_.fail(key, "expected draft, default or high, got " + v->dump());
    x = value;
  }
  template <size_t N>
  void numbers(const std::string& key, Opt<std::array<double, N>>& x, const Range& r, Need need = kOptional) {
    const Json* v = find(key, need);
    if (!v) return;
    if (!v->is_array() || v->size() != N)
      at_.fail(key, "expected an array of " + std::to_string(N) + " numbers, got " + shape_of(*v));
    std::array<double, N> out{};
    for (size_t i = 0; i < N; ++i) out[i] = to_number((*v)[i], key + "/" + std::to_string(i), r);
    x = out;
  }
  template <size_t N>
  void integers(const std::string& key, Opt<std::array<int, N>>& x, const Range& r, Need need = kOptional) {
    const Json* v = find(key, need);
    if (!v) return;
    if (!v->is_array() || v->size() != N)
      at_.fail(key, "expected an array of " + std::to_string(N) + " integers, got " + shape_of(*v));
    std::array<int, N> out{};
    for (size_t i = 0; i < N; ++i) {
      const std::string element = key + "/" + std::to_string(i);
      if (!(*v)[i].is_number_integer()) at_.fail(element, "expected an integer, got " + json_type_name((*v)[i]));
      at_.number(element, (*v)[i].get<double>(), r);
      out[i] = (*v)[i].get<int>();
    }
    x = out;
  }
  void number_list(const std::string& key, Opt<std::vector<double>>& x, size_t min_length, const Range& r,
                   Need need = kOptional) {
    const Json* v = array(key, need, min_length);
    if (!v) return;
    std::vector<double> out;
    for (size_t i = 0; i < v->size(); ++i) out.push_back(to_number((*v)[i], key + "/" + std::to_string(i), r));
    x = std::move(out);
  }
  void points2(const std::string& key, Opt<std::vector<Vec2>>& x, size_t min_count, Need need = kOptional) {
    const Json* v = array(key, need, 0);
    if (!v) return;
    at_.point_count(key, v->size(), min_count);
    std::vector<Vec2> out;
    for (size_t i = 0; i < v->size(); ++i) {
      const Json& c = (*v)[i];
      if (!c.is_array() || c.size() != 2 || !c[0].is_number() || !c[1].is_number())
        at_.fail(key + "/" + std::to_string(i), kPointMessage);
      out.push_back({c[0].get<double>(), c[1].get<double>()});
      at_.point2(key + "/" + std::to_string(i), out.back());
    }
    x = std::move(out);
  }
  void points3(const std::string& key, Opt<std::vector<Vec3>>& x, Need need = kOptional) {
    const Json* v = array(key, need, 0);
    if (!v) return;
    std::vector<Vec3> out;
    for (size_t i = 0; i < v->size(); ++i) {
      const std::string p = key + "/" + std::to_string(i);
      const Json& c = (*v)[i];
      if (!c.is_array() || c.size() != 3) at_.fail(p, "expected a point [x, y, z]");
      Vec3 point{};
      for (size_t d = 0; d < 3; ++d) {
        if (!c[d].is_number()) at_.fail(p + "/" + std::to_string(d), "expected a finite number");
        point[d] = c[d].get<double>();
      }
      at_.point3(p, point);
      out.push_back(point);
    }
    x = std::move(out);
  }
  void index_pairs(const std::string& key, Opt<std::vector<Int2>>& x, size_t min_count, Need need = kOptional) {
    const Json* v = array(key, need, min_count);
    if (!v) return;
    std::vector<Int2> out;
    for (size_t k = 0; k < v->size(); ++k) {
      const Json& c = (*v)[k];
      if (!c.is_array() || c.size() != 2 || !c[0].is_number_integer() || !c[1].is_number_integer())
        at_.fail(key + "/" + std::to_string(k), "expected a control point index pair [i, j]");
      for (size_t d = 0; d < 2; ++d)  // an int, so that no index wraps around (the build checks the net)
        at_.number(key + "/" + std::to_string(k) + "/" + std::to_string(d), c[d].get<double>(), kIntRange);
      out.push_back({c[0].get<int>(), c[1].get<int>()});
    }
    x = std::move(out);
  }
  void shell_ref(const std::string& key, Opt<ShellRef>& x, Need need = kOptional) {
    const Json* v = find(key, need);
    if (!v) return;
    if (v->is_string()) {
      x = v->get<std::string>();
      at_.text(key, std::get<std::string>(*x));
      return;
    }
    if (!v->is_number_integer())
      at_.fail(key, "expected an integer, got " + json_type_name(*v) +
                        (v->is_number() ? " " + format_value(v->get<double>()) : ""));
    at_.number(key, v->get<double>(), kIntRange);
    x = v->get<int>();
  }
  void limit(const std::string& key, Opt<VerifyLimit>& x, const Range& r) {
    const Json* v = find(key, kOptional);
    if (!v) return;
    x = VerifyLimit{};
    if (!v->is_null()) x->value = to_number(*v, key, r);
  }
  template <class T>
  void object(const std::string& key, Opt<T>& x, Need need = kOptional) {
    if (const Json* v = find(key, need)) read_object(key, *v, x.emplace());
  }
  template <class T>
  void object(const std::string& key, T& x) {
    if (const Json* v = find(key, kOptional)) read_object(key, *v, x);
  }
  template <class T>
  void objects(const std::string& key, std::vector<T>& list, size_t min_length) {
    const Json* v = array(key, kOptional, min_length);
    if (!v) return;
    for (size_t i = 0; i < v->size(); ++i) read_object(key + "/" + std::to_string(i), (*v)[i], list.emplace_back());
  }
  template <class T>
  void objects(const std::string& key, Opt<std::vector<T>>& list, size_t min_length) {
    if (json_.contains(key)) objects(key, list.emplace(), min_length);
  }
  template <class Rule>
  void check(const std::string& key, Rule&& rule) {
    const std::string problem = rule();
    if (!problem.empty()) at_.fail(key, problem);
  }

  // Rejects keys that no declaration asked for (a typo must not be silently ignored).
  void finish() const {
    for (auto it = json_.begin(); it != json_.end(); ++it) {
      if (known_.count(it.key())) continue;
      std::string list;
      for (const auto& k : known_) list += (list.empty() ? "" : ", ") + k;
      at_.fail(it.key(), "unknown key \"" + it.key() + "\": allowed here are " + list);
    }
  }

 private:
  const Json* find(const std::string& key, Need need) {
    known_.insert(key);
    auto it = json_.find(key);
    if (it == json_.end()) {
      if (need == kRequired) at_.fail(key, "required key is missing");
      return nullptr;
    }
    return &*it;
  }
  const Json* array(const std::string& key, Need need, size_t min_length) {
    const Json* v = find(key, need);
    if (!v) return nullptr;
    if (!v->is_array()) at_.fail(key, "expected an array, got " + json_type_name(*v));
    at_.element_count(key, v->size(), min_length);
    return v;
  }
  double to_number(const Json& v, const std::string& key, const Range& r) const {
    if (!v.is_number()) at_.fail(key, "expected a number, got " + json_type_name(v));
    at_.number(key, v.get<double>(), r);
    return v.get<double>();
  }
  static std::string shape_of(const Json& v) {
    return v.is_array() ? "an array of " + std::to_string(v.size()) : json_type_name(v);
  }
  template <class T>
  void read_object(const std::string& key, const Json& v, T& x) const {
    JsonReader child(v, at_.child(key), at_.file());
    describe(child, x);
    child.finish();
  }

  const Json& json_;
  FieldChecks at_;
  std::set<std::string> known_;
};

}  // namespace

Scene read_scene(const nlohmann::json& document, const std::string& source) {
  Scene scene;
  scene.source = source;
  JsonReader root(document, "", source);
  describe(root, scene);
  root.finish();
  return scene;
}

Scene read_scene(const std::string& json_text, const std::string& source) {
  return read_scene(parse_json_strictly(json_text, source), source);
}

Scene load_scene(const std::string& path) { return read_scene(read_scene_file(path), path); }

Scene default_scene() { return read_scene(std::string(default_scene_json()), "<built-in default>"); }

}  // namespace shellfrac::scene
