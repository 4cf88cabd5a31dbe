// The JSON writer of the scene format: walks scene/describe.hpp and writes every field that is set.
#include "scene/describe.hpp"
#include "scene/json_io.hpp"

namespace shellfrac::scene {

namespace {

using Json = nlohmann::json;

class JsonWriter {
 public:
  Json json = Json::object();

  template <class T, class... Ignored>
  void number(const std::string& key, const Opt<T>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class... Ignored>
  void integer(const std::string& key, const Opt<int>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class... Ignored>
  void boolean(const std::string& key, const Opt<bool>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class... Ignored>
  void string(const std::string& key, const Opt<std::string>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  void choice(const std::string& key, const Opt<std::string>& x, const std::vector<std::string>&, Need = kOptional) {
    if (x) json[key] = *x;
  }
  void choices(const std::string& key, const Opt<std::vector<std::string>>& x, const std::vector<std::string>&, size_t,
               Need = kOptional) {
    if (x) json[key] = *x;
  }
  void quality(const std::string& key, const Opt<std::string>& x) {
    if (x) json[key] = *x;
  }
  template <class T, size_t N, class... Ignored>
  void numbers(const std::string& key, const Opt<std::array<T, N>>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class T, size_t N, class... Ignored>
  void integers(const std::string& key, const Opt<std::array<T, N>>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class T, class... Ignored>
  void number_list(const std::string& key, const Opt<std::vector<T>>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class... Ignored>
  void points2(const std::string& key, const Opt<std::vector<Vec2>>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class... Ignored>
  void points3(const std::string& key, const Opt<std::vector<Vec3>>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class... Ignored>
  void index_pairs(const std::string& key, const Opt<std::vector<Int2>>& x, const Ignored&...) {
    if (x) json[key] = *x;
  }
  template <class... Ignored>
  void shell_ref(const std::string& key, const Opt<ShellRef>& x, const Ignored&...) {
    if (!x) return;
    if (const auto* name = std::get_if<std::string>(&*x))
      json[key] = *name;
    else
      json[key] = std::get<int>(*x);
  }
  void limit(const std::string& key, const Opt<VerifyLimit>& x, const Range&) {
    if (x) json[key] = x->value ? Json(*x->value) : Json(nullptr);
  }
  template <class T>
  void object(const std::string& key, Opt<T>& x, Need = kOptional) {
    if (x) json[key] = write(*x);  // a present object is written even when empty: its presence means something
  }
  template <class T>
  void object(const std::string& key, T& x) {
    Json j = write(x);
    if (!j.empty()) json[key] = std::move(j);
  }
  template <class T>
  void objects(const std::string& key, std::vector<T>& list, size_t) {
    if (list.empty()) return;
    Json a = Json::array();
    for (T& item : list) a.push_back(write(item));
    json[key] = std::move(a);
  }
  template <class T>
  void objects(const std::string& key, Opt<std::vector<T>>& list, size_t) {
    if (!list) return;
    Json a = Json::array();
    for (T& item : *list) a.push_back(write(item));
    json[key] = std::move(a);
  }
  template <class Rule>
  void check(const std::string&, Rule&&) {}

 private:
  template <class T>
  static Json write(T& x) {
    JsonWriter child;
    describe(child, x);
    return std::move(child.json);
  }
};

}  // namespace

nlohmann::json to_json(const Scene& scene) {
  Scene copy = scene;  // the declarations take their fields by reference; nothing is changed
  JsonWriter w;
  describe(w, copy);
  return std::move(w.json);
}

}  // namespace shellfrac::scene
