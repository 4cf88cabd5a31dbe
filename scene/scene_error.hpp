#pragma once
#include <string>

#include "core/error.hpp"

namespace shellfrac::scene {

// Bad user input: a scene that cannot be read, parsed or accepted. Carries the file, the JSON pointer of
// the offending value (e.g. "/shells/0/material/E") and what is wrong and allowed. Exit code 2.
class SceneError : public core::InputError {
 public:
  SceneError(std::string file, std::string json_path, std::string message)
      : core::InputError(format(file, json_path, message)),
        file_(std::move(file)),
        json_path_(std::move(json_path)),
        message_(std::move(message)) {}

  const std::string& file() const { return file_; }
  const std::string& json_path() const { return json_path_; }
  const std::string& message() const { return message_; }

 private:
  static std::string format(const std::string& file, const std::string& path, const std::string& message) {
    std::string s = file;
    if (!path.empty()) s += ": " + path;
    return s + ": " + message;
  }
  std::string file_, json_path_, message_;
};

}  // namespace shellfrac::scene
