#pragma once

namespace shellfrac::core {

inline constexpr double kPi = 3.14159265358979323846;

}  // namespace shellfrac::core
