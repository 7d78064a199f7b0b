// Numbers in error messages, printed as a stream prints them (1, 0.5, 1e+30, nan, inf).
#pragma once

#include <sstream>
#include <string>

namespace clraster::io {

inline std::string format_number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace clraster::io
