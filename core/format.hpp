#pragma once
// The one number formatter for messages, logs and tables.
#include <string>

namespace shellfrac::core {

// printf %g style with `digits` significant digits ("0.0004167", "1.2e+07"); "nan", "inf", "-inf"
// for non-finite values.
std::string format_number(double v, int digits = 6);
// "1:02:03" or "2:03" from seconds.
std::string format_duration(double seconds);

}  // namespace shellfrac::core
