// Strict reading of scene text. nlohmann's DOM parser keeps the last of two equal keys and
// reports an overflowing number without a position, so the text is first walked by a small scanner that
// knows where it is (JSON pointer, byte offset) and refuses what the DOM would hide. The scanner only
// judges what it understands; a syntax error makes it stop, and nlohmann's parser then reports it with
// its own words and our line and column.
#include "scene/strict_json.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <vector>

#include "scene/scene_error.hpp"

namespace shellfrac::scene {

std::string line_and_column(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

std::string read_scene_file(const std::string& path, std::size_t max_bytes) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0)
    throw SceneError(path, "", "cannot open the scene file: " + std::string(std::strerror(errno)));
  if (S_ISDIR(info.st_mode)) throw SceneError(path, "", "is a directory, not a scene file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw SceneError(path, "", "cannot open the scene file: " + std::string(std::strerror(errno)));
  // Read in chunks up to one byte past the cap: devices and pipes report no size, so the cap is checked
  // on what was read, never on what stat claims.
  std::string text;
  char buffer[1 << 16];
  while (text.size() <= max_bytes) {
    const std::size_t n = std::fread(buffer, 1, sizeof buffer, f);
    text.append(buffer, n);
    if (n < sizeof buffer) break;
  }
  const bool failed = std::ferror(f) != 0;
  const int error = errno;
  std::fclose(f);
  if (failed) throw SceneError(path, "", "cannot read the scene file: " + std::string(std::strerror(error)));
  if (text.size() > max_bytes)
    throw SceneError(path, "", "the scene file is larger than the limit of " + std::to_string(max_bytes >> 20) +
                                   " MiB (docs/scene-format.md, \"Limits\")");
  return text;
}

namespace {

// "~" and "/" escaped as RFC 6901 asks.
std::string pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

void append_utf8(std::string& out, unsigned code) {
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xC0 | (code >> 6));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xE0 | (code >> 12));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (code >> 18));
    out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (code & 0x3F));
  }
}

// Walks JSON text by its grammar. Returns false (and stops) at the first syntax error, which the DOM
// parser then reports; throws SceneError for what is syntactically fine but not accepted.
class Scanner {
 public:
  Scanner(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  bool document() {
    skip_space();
    if (!value("", 0)) return false;
    skip_space();
    return at_ == text_.size();
  }

 private:
  [[noreturn]] void fail(const std::string& pointer, std::size_t offset, const std::string& message) const {
    throw SceneError(source_, pointer.empty() ? "/" : pointer, message + " (" + line_and_column(text_, offset) + ")");
  }
  void skip_space() {
    while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\t' || text_[at_] == '\n' || text_[at_] == '\r'))
      ++at_;
  }
  bool literal(const char* word) {
    const std::size_t n = std::strlen(word);
    if (text_.compare(at_, n, word) != 0) return false;
    at_ += n;
    return true;
  }
  bool value(const std::string& pointer, int depth) {
    if (at_ >= text_.size()) return false;
    const char c = text_[at_];
    if (c == '{' || c == '[') {
      if (depth >= kMaxJsonDepth)
        fail(pointer, at_, "nesting deeper than " + std::to_string(kMaxJsonDepth) + " objects and arrays");
      return c == '{' ? object(pointer, depth + 1) : array(pointer, depth + 1);
    }
    if (c == '"') {
      std::string ignored;
      return string(ignored);
    }
    if (c == 't') return literal("true");
    if (c == 'f') return literal("false");
    if (c == 'n') return literal("null");
    return number(pointer);
  }
  bool object(const std::string& pointer, int depth) {
    ++at_;  // '{'
    skip_space();
    if (at_ < text_.size() && text_[at_] == '}') {
      ++at_;
      return true;
    }
    std::set<std::string> keys;
    while (true) {
      skip_space();
      const std::size_t key_at = at_;
      std::string key;
      if (at_ >= text_.size() || text_[at_] != '"' || !string(key)) return false;
      const std::string child = pointer + "/" + pointer_token(key);
      if (!keys.insert(key).second) fail(child, key_at, "duplicate key \"" + key + "\": each key may appear once in an object");
      skip_space();
      if (at_ >= text_.size() || text_[at_] != ':') return false;
      ++at_;
      skip_space();
      if (!value(child, depth)) return false;
      skip_space();
      if (at_ >= text_.size()) return false;
      if (text_[at_] == ',') {
        ++at_;
        continue;
      }
      if (text_[at_] != '}') return false;
      ++at_;
      return true;
    }
  }
  bool array(const std::string& pointer, int depth) {
    ++at_;  // '['
    skip_space();
    if (at_ < text_.size() && text_[at_] == ']') {
      ++at_;
      return true;
    }
    for (std::size_t index = 0;; ++index) {
      skip_space();
      if (!value(pointer + "/" + std::to_string(index), depth)) return false;
      skip_space();
      if (at_ >= text_.size()) return false;
      if (text_[at_] == ',') {
        ++at_;
        continue;
      }
      if (text_[at_] != ']') return false;
      ++at_;
      return true;
    }
  }
  bool hex4(unsigned& code) {
    if (at_ + 4 > text_.size()) return false;
    code = 0;
    for (int k = 0; k < 4; ++k) {
      const char h = text_[at_++];
      code <<= 4;
      if (h >= '0' && h <= '9')
        code |= static_cast<unsigned>(h - '0');
      else if (h >= 'a' && h <= 'f')
        code |= static_cast<unsigned>(h - 'a' + 10);
      else if (h >= 'A' && h <= 'F')
        code |= static_cast<unsigned>(h - 'A' + 10);
      else
        return false;
    }
    return true;
  }
  // A string token, decoded into `out` (escapes resolved) so that equal keys compare equal however they
  // were spelled. UTF-8 validity is left to the DOM parser.
  bool string(std::string& out) {
    ++at_;  // opening quote
    while (at_ < text_.size()) {
      const char c = text_[at_++];
      if (c == '"') return true;
      if (static_cast<unsigned char>(c) < 0x20) return false;  // raw control character: a syntax error
      if (c != '\\') {
        out += c;
        continue;
      }
      if (at_ >= text_.size()) return false;
      const char e = text_[at_++];
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          unsigned code = 0;
          if (!hex4(code)) return false;
          if (code >= 0xD800 && code < 0xDC00) {  // high surrogate: a low one must follow
            unsigned low = 0;
            if (!literal("\\u") || !hex4(low) || low < 0xDC00 || low > 0xDFFF) return false;
            code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
          } else if (code >= 0xDC00 && code <= 0xDFFF) {
            return false;
          }
          append_utf8(out, code);
          break;
        }
        default: return false;
      }
    }
    return false;
  }
  bool number(const std::string& pointer) {
    const std::size_t start = at_;
    auto digits = [&] {
      const std::size_t from = at_;
      while (at_ < text_.size() && text_[at_] >= '0' && text_[at_] <= '9') ++at_;
      return at_ > from;
    };
    if (at_ < text_.size() && text_[at_] == '-') ++at_;
    if (at_ < text_.size() && text_[at_] == '0')
      ++at_;
    else if (!digits())
      return false;
    if (at_ < text_.size() && text_[at_] == '.') {
      ++at_;
      if (!digits()) return false;
    }
    if (at_ < text_.size() && (text_[at_] == 'e' || text_[at_] == 'E')) {
      ++at_;
      if (at_ < text_.size() && (text_[at_] == '+' || text_[at_] == '-')) ++at_;
      if (!digits()) return false;
    }
    const std::string token = text_.substr(start, at_ - start);
    const double v = std::strtod(token.c_str(), nullptr);
    if (std::isinf(v))
      fail(pointer, start, "number " + token + " is too large for a double (largest is about 1.8e308)");
    return true;
  }

  const std::string& text_;
  const std::string& source_;
  std::size_t at_ = 0;
};

}  // namespace

nlohmann::json parse_json_strictly(const std::string& text, const std::string& source) {
  Scanner(text, source).document();  // throws for duplicates, overflow and depth; stops at syntax errors
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // parse_error.byte is one past the offending character; other errors carry no position.
    const auto* parse = dynamic_cast<const nlohmann::json::parse_error*>(&e);
    const std::size_t byte = parse && parse->byte ? parse->byte - 1 : 0;
    throw SceneError(source, "", "invalid JSON" + (parse ? " at " + line_and_column(text, byte) : std::string()) + ": " +
                                     std::string(e.what()));
  }
}

}  // namespace shellfrac::scene
