// libFuzzer entry point of the scene reader (built by scripts/fuzz_scene_reader.sh with clang,
// AddressSanitizer and UndefinedBehaviorSanitizer). Refused inputs are fine; anything that escapes
// check_scene_text (an unexpected exception, a sanitizer report, a crash) stops the fuzzer.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/scene_reader_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  shellfrac::fuzz::check_scene_text(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
