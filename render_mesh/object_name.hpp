#pragma once
#include <string>

namespace shellfrac::render_mesh {

// The name an object gets in every exported file. A scene may name a shell anything (a name
// holding "\nv 9 9 9" would inject geometry into an OBJ), so every writer passes names through this:
//   - the name is read as UTF-8; every byte that is not part of a valid UTF-8 sequence becomes '_';
//   - every code point that ends or breaks a line or controls a terminal becomes '_': C0 controls
//     U+0000-U+001F (newline, carriage return, tab, ...), U+007F, C1 controls U+0080-U+009F (NEL),
//     and the line and paragraph separators U+2028, U+2029 (Python's splitlines breaks at all of them);
//   - space and '#' become '_' (OBJ splits group names at white space and some readers start a
//     comment at '#');
//   - the result is cut to at most 255 bytes at a code point boundary;
//   - an empty result is replaced by `fallback` (which is sanitised the same way).
// Everything else (letters of any script, digits, punctuation) is kept, so ordinary names pass unchanged
// and the same name appears in OBJ, PLY, glTF and every assimp format.
std::string export_object_name(const std::string& name, const std::string& fallback);

}  // namespace shellfrac::render_mesh
