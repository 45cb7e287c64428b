#pragma once
// printf-style text of up to five numbers, for the station's reports and plots.
#include <cstdio>
#include <string>

namespace nav::station {

/// `pattern` filled in with a ... e as std::snprintf fills it (the ones it names), cut at 255
/// characters.
inline std::string format_numbers(const char* pattern, double a = 0.0, double b = 0.0, double c = 0.0, double d = 0.0,
                                  double e = 0.0) {
  char text[256];
  std::snprintf(text, sizeof(text), pattern, a, b, c, d, e);
  return text;
}

}  // namespace nav::station
