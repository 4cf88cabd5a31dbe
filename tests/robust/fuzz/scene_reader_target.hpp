#pragma once
// The fuzz target of the scene reader, shared by the libFuzzer build
// (scripts/fuzz_scene_reader.sh) and the bounded mutation test of the suite.
#include <string>

namespace shellfrac::fuzz {

// Feeds one scene text through what `validate` does before building: strict parsing, the format's
// checks, the resource estimate (mesh files resolved against a folder that does not exist) and a
// 256 MiB budget; accepted scenes must write back to the same document. Returns 0 when accepted,
// 1 when refused with an InputError (exit code 2). Anything else escapes: another exception type, a
// round trip that changes the document (std::logic_error), or a crash is a bug.
int check_scene_text(const std::string& text);

}  // namespace shellfrac::fuzz
