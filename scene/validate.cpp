// The validator of scenes built in C++: walks scene/describe.hpp over the values and applies the checks
// the JSON reader applies while parsing (field_checks.hpp), so both paths refuse the same scenes with the
// same messages.
#include "scene/validate.hpp"

#include "scene/describe.hpp"
#include "scene/field_checks.hpp"

namespace shellfrac::scene {

namespace {

class Validator {
 public:
  Validator(std::string path, const std::string& file) : at_(file, std::move(path)) {}

  void number(const std::string& key, const Opt<double>& x, const Range& r, Need need = kOptional) {
    if (present(key, x, need)) at_.number(key, *x, r);
  }
  void integer(const std::string& key, const Opt<int>& x, const Range& r, Need need = kOptional) {
    if (present(key, x, need)) at_.number(key, *x, r);
  }
  void boolean(const std::string& key, const Opt<bool>& x, Need need = kOptional) { present(key, x, need); }
  void string(const std::string& key, const Opt<std::string>& x, Need need = kOptional) {
    if (present(key, x, need)) at_.text(key, *x);
  }
  void choice(const std::string& key, const Opt<std::string>& x, const std::vector<std::string>& allowed,
              Need need = kOptional) {
    if (present(key, x, need)) at_.choice(key, *x, allowed);
  }
  void choices(const std::string& key, const Opt<std::vector<std::string>>& x, const std::vector<std::string>& allowed,
               size_t min_length, Need need = kOptional) {
    if (!present(key, x, need)) return;
    at_.element_count(key, x->size(), min_length);
    for (size_t i = 0; i < x->size(); ++i) at_.choice(key + "/" + std::to_string(i), (*x)[i], allowed);
  }
  void quality(const std::string& key, const Opt<std::string>& x) {
    if (x && !is_quality(*x)) at_.fail(key, "expected draft, default or high, got \"" + *x + "\"");
  }
  template <size_t N>
  void numbers(const std::string& key, const Opt<std::array<double, N>>& x, const Range& r, Need need = kOptional) {
    if (present(key, x, need))
      for (size_t i = 0; i < N; ++i) at_.number(key + "/" + std::to_string(i), (*x)[i], r);
  }
  template <size_t N>
  void integers(const std::string& key, const Opt<std::array<int, N>>& x, const Range& r, Need need = kOptional) {
    if (present(key, x, need))
      for (size_t i = 0; i < N; ++i) at_.number(key + "/" + std::to_string(i), (*x)[i], r);
  }
  void number_list(const std::string& key, const Opt<std::vector<double>>& x, size_t min_length, const Range& r,
                   Need need = kOptional) {
    if (!present(key, x, need)) return;
    at_.element_count(key, x->size(), min_length);
    for (size_t i = 0; i < x->size(); ++i) at_.number(key + "/" + std::to_string(i), (*x)[i], r);
  }
  void points2(const std::string& key, const Opt<std::vector<Vec2>>& x, size_t min_count, Need need = kOptional) {
    if (!present(key, x, need)) return;
    at_.point_count(key, x->size(), min_count);
    for (size_t i = 0; i < x->size(); ++i) at_.point2(key + "/" + std::to_string(i), (*x)[i]);
  }
  void points3(const std::string& key, const Opt<std::vector<Vec3>>& x, Need need = kOptional) {
    if (!present(key, x, need)) return;
    for (size_t i = 0; i < x->size(); ++i) at_.point3(key + "/" + std::to_string(i), (*x)[i]);
  }
  void index_pairs(const std::string& key, const Opt<std::vector<Int2>>& x, size_t min_count, Need need = kOptional) {
    if (present(key, x, need)) at_.element_count(key, x->size(), min_count);
  }
  void shell_ref(const std::string& key, const Opt<ShellRef>& x, Need need = kOptional) {
    if (present(key, x, need))
      if (const auto* name = std::get_if<std::string>(&*x)) at_.text(key, *name);
  }
  void limit(const std::string& key, const Opt<VerifyLimit>& x, const Range& r) {
    if (x && x->value) at_.number(key, *x->value, r);
  }
  template <class T>
  void object(const std::string& key, Opt<T>& x, Need need = kOptional) {
    if (present(key, x, need)) validate_object(key, *x);
  }
  template <class T>
  void object(const std::string& key, T& x) {
    validate_object(key, x);
  }
  template <class T>
  void objects(const std::string& key, std::vector<T>& list, size_t min_length) {
    at_.element_count(key, list.size(), min_length);
    for (size_t i = 0; i < list.size(); ++i) validate_object(key + "/" + std::to_string(i), list[i]);
  }
  template <class T>
  void objects(const std::string& key, Opt<std::vector<T>>& list, size_t min_length) {
    if (list) objects(key, *list, min_length);
  }
  template <class Rule>
  void check(const std::string& key, Rule&& rule) {
    const std::string problem = rule();
    if (!problem.empty()) at_.fail(key, problem);
  }

 private:
  template <class T>
  bool present(const std::string& key, const Opt<T>& x, Need need) const {
    if (!x && need == kRequired) at_.fail(key, "required key is missing");
    return x.has_value();
  }
  template <class T>
  void validate_object(const std::string& key, T& x) const {
    Validator child(at_.child(key), at_.file());
    describe(child, x);
  }

  FieldChecks at_;
};

// Pins and interfaces name shells, so two shells of one name would make a reference ambiguous (the
// first would silently win). Unnamed shells are called "shell<index>" (scene/build_shells.cpp), so
// those names count too.
void check_unique_shell_names(const Scene& scene) {
  const FieldChecks at(scene.source, "");
  std::vector<std::string> names;
  for (size_t i = 0; i < scene.shells.size(); ++i) {
    const std::string name = scene.shells[i].name.value_or("shell" + std::to_string(i));
    for (size_t k = 0; k < names.size(); ++k)
      if (names[k] == name)
        at.fail("shells/" + std::to_string(i) + (scene.shells[i].name ? "/name" : ""),
                "shell name \"" + name + "\" is already used by /shells/" + std::to_string(k) +
                    " (pins and interfaces name shells, so names must be unique)");
    names.push_back(name);
  }
}

}  // namespace

void validate(const Scene& scene) {
  Scene copy = scene;  // the declarations take their fields by reference; nothing is changed
  Validator root("", scene.source);
  describe(root, copy);
  check_unique_shell_names(scene);
}

}  // namespace shellfrac::scene
