#pragma once
// A tiny XML tag scanner, enough for VTK's XML files: it finds the next tag, skipping text,
// comments, <?...?> and <!...> declarations, and splits it into name and attributes.
// It does not validate nesting, expand entities or read CDATA. Not a public API.
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "nav/mesh/text_lines.hpp"

namespace nav::detail {

/// One tag: <name key="value" ...>, </name> or <name ... />.
struct XmlTag {
  std::string_view name;
  bool closing = false;       ///< </name>
  bool self_closing = false;  ///< <name ... />
  std::vector<std::pair<std::string_view, std::string_view>> attributes;

  /// The value of attribute `key`, or nullopt.
  std::optional<std::string_view> attribute(std::string_view key) const;
};

/// What read_xml_tag found.
enum class XmlRead { tag, end_of_text, error };

/// Moves past the next tag (the cursor ends just after its '>') and parses it into `tag`.
/// Text before the tag is skipped. A malformed or unterminated tag records an Error in `scanner`.
XmlRead read_xml_tag(TextScanner& scanner, XmlTag& tag);

}  // namespace nav::detail
