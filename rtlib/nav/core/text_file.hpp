#pragma once
// Writing a text (a report, a plot, a JSON result) to a file. Init-time and tool code only.
#include <string>
#include <string_view>

#include "nav/core/error.hpp"

namespace nav {

/// Writes the whole of `text` to `path`, replacing the file; an Error names the file when it
/// cannot be written.
Status write_text_file(const std::string& path, std::string_view text);

}  // namespace nav
