#include "nav/core/text_file.hpp"

#include <fstream>

namespace nav {

Status write_text_file(const std::string& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) return Error{.message = "cannot write the file", .file = path};
  return Done{};
}

}  // namespace nav
