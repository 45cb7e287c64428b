#include "nav/mesh/xml_tag_reader.hpp"

#include <algorithm>
#include <string>

namespace nav::detail {
namespace {

constexpr std::string_view kSpaces = " \t\r\n";

std::string_view trim(std::string_view text) {
  const std::size_t first = text.find_first_not_of(kSpaces);
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(kSpaces) - first + 1);
}

/// Moves past a comment "<!-- ... -->" whose "<!--" is under the cursor.
bool skip_comment(TextScanner& scanner) {
  scanner.advance(4);
  while (true) {
    const auto body = scanner.take_until('>');
    if (!body) return scanner.fail("xml", "unexpected end of file inside a comment");
    scanner.advance(1);
    if (body->ends_with("--")) return true;
  }
}

/// Splits the inside of a tag (between '<' and '>') into name and attributes.
bool parse_tag(TextScanner& scanner, std::string_view inside, XmlTag& tag) {
  tag = XmlTag{};
  if (inside.starts_with('/')) {
    tag.closing = true;
    inside.remove_prefix(1);
  }
  if (inside.ends_with('/')) {
    tag.self_closing = true;
    inside.remove_suffix(1);
  }
  inside = trim(inside);
  const std::size_t name_end = std::min(inside.find_first_of(kSpaces), inside.size());
  tag.name = inside.substr(0, name_end);
  if (tag.name.empty()) return scanner.fail("xml", "a tag without a name");
  std::string_view rest = trim(inside.substr(name_end));
  while (!rest.empty()) {
    const std::size_t equals = rest.find('=');
    if (equals == std::string_view::npos)
      return scanner.fail(tag.name, "malformed attribute '" + std::string(rest) + "'");
    const std::string_view key = trim(rest.substr(0, equals));
    rest = trim(rest.substr(equals + 1));
    if (rest.empty() || (rest.front() != '"' && rest.front() != '\'')) {
      return scanner.fail(tag.name, "attribute '" + std::string(key) + "' has no quoted value");
    }
    const std::size_t close = rest.find(rest.front(), 1);
    if (close == std::string_view::npos) {
      return scanner.fail(tag.name, "attribute '" + std::string(key) + "' has an unterminated value");
    }
    tag.attributes.emplace_back(key, rest.substr(1, close - 1));
    rest = trim(rest.substr(close + 1));
  }
  return true;
}

}  // namespace

std::optional<std::string_view> XmlTag::attribute(std::string_view key) const {
  for (const auto& [name, value] : attributes) {
    if (name == key) return value;
  }
  return std::nullopt;
}

XmlRead read_xml_tag(TextScanner& scanner, XmlTag& tag) {
  while (true) {
    if (!scanner.take_until('<')) return XmlRead::end_of_text;
    if (scanner.peek(Within::line).starts_with("<!--")) {
      if (!skip_comment(scanner)) return XmlRead::error;
      continue;
    }
    scanner.advance(1);
    const auto inside = scanner.take_until('>');
    if (!inside) {
      scanner.fail("xml", "unexpected end of file inside a tag");
      return XmlRead::error;
    }
    scanner.advance(1);
    if (inside->starts_with('?') || inside->starts_with('!')) continue;
    return parse_tag(scanner, *inside, tag) ? XmlRead::tag : XmlRead::error;
  }
}

}  // namespace nav::detail
