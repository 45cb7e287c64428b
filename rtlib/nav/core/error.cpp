#include "nav/core/error.hpp"

namespace nav {

std::string Error::describe() const {
  std::string text;
  if (!file.empty()) {
    text += file;
    if (line > 0) text += ":" + std::to_string(line);
    text += ": ";
  }
  if (!field.empty()) text += field + ": ";
  text += message;
  return text;
}

}  // namespace nav
