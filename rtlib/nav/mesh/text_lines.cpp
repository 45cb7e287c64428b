#include "nav/mesh/text_lines.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <utility>

namespace nav {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::string_view strip_plus(std::string_view token) {
  if (token.size() > 1 && token.front() == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  return token;
}

}  // namespace

Result<std::string> read_text_file(const std::string& path) {
  std::error_code code;
  const auto status = std::filesystem::status(path, code);
  if (code || !std::filesystem::exists(status)) return Error{.message = "cannot open file: no such file", .file = path};
  if (!std::filesystem::is_regular_file(status))
    return Error{.message = "cannot open file: not a regular file", .file = path};
  std::ifstream stream(path, std::ios::binary);
  if (!stream) return Error{.message = "cannot open file", .file = path};
  const auto size = std::filesystem::file_size(path, code);
  if (code) return Error{.message = "cannot read file size", .file = path};
  std::string text(size, '\0');
  stream.read(text.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(stream.gcount()) != size) return Error{.message = "cannot read file", .file = path};
  return text;
}

std::optional<double> parse_double(std::string_view token) {
  token = strip_plus(token);
  double value = 0.0;
  const char* end = token.data() + token.size();
  const auto [next, code] = std::from_chars(token.data(), end, value);
  if (code != std::errc() || next != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::int64_t> parse_int(std::string_view token) {
  token = strip_plus(token);
  std::int64_t value = 0;
  const char* end = token.data() + token.size();
  const auto [next, code] = std::from_chars(token.data(), end, value);
  if (code != std::errc() || next != end) return std::nullopt;
  return value;
}

int line_of_token(std::string_view text, int first_line, std::size_t token_index) {
  int line = first_line;
  int token_line = first_line;
  std::size_t tokens = 0;
  bool in_token = false;
  for (const char c : text) {
    if (is_space(c)) {
      in_token = false;
      if (c == '\n') ++line;
      continue;
    }
    if (in_token) continue;
    in_token = true;
    token_line = line;
    if (tokens++ == token_index) return line;
  }
  return token_line;
}

TextScanner::TextScanner(std::string path, std::string_view text, int first_line)
    : path_(std::move(path)), text_(text), line_(first_line) {}

void TextScanner::skip_spaces(Within within) {
  while (position_ < text_.size() && is_space(text_[position_])) {
    if (text_[position_] == '\n') {
      if (within == Within::line) return;
      ++line_;
    }
    ++position_;
  }
}

bool TextScanner::read(std::string_view& token, std::string_view field, Within within) {
  skip_spaces(within);
  if (position_ == text_.size()) return fail(field, "unexpected end of file");
  if (text_[position_] == '\n') return fail(field, "missing value at end of line");
  const std::size_t start = position_;
  while (position_ < text_.size() && !is_space(text_[position_])) ++position_;
  token = text_.substr(start, position_ - start);
  return true;
}

bool TextScanner::read(double& value, std::string_view field, Within within) {
  std::string_view token;
  if (!read(token, field, within)) return false;
  const auto parsed = parse_double(token);
  if (!parsed) return fail(field, "'" + std::string(token) + "' is not a finite number");
  value = *parsed;
  return true;
}

bool TextScanner::read(std::int64_t& value, std::string_view field, Within within) {
  std::string_view token;
  if (!read(token, field, within)) return false;
  const auto parsed = parse_int(token);
  if (!parsed) return fail(field, "'" + std::string(token) + "' is not an integer");
  value = *parsed;
  return true;
}

bool TextScanner::read_in_range(std::int64_t& value, std::int64_t min_value, std::int64_t max_value,
                                std::string_view field, Within within) {
  if (!read(value, field, within)) return false;
  if (value < min_value || value > max_value) {
    return fail(field, std::to_string(value) + " is out of range [" + std::to_string(min_value) + ", " +
                           std::to_string(max_value) + "]");
  }
  return true;
}

std::string_view TextScanner::peek(Within within) {
  skip_spaces(within);
  std::size_t end = position_;
  while (end < text_.size() && !is_space(text_[end])) ++end;
  return text_.substr(position_, end - position_);
}

bool TextScanner::expect(std::string_view word, std::string_view field, Within within) {
  std::string_view token;
  if (!read(token, field, within)) return false;
  if (token != word) return fail(field, "expected '" + std::string(word) + "', found '" + std::string(token) + "'");
  return true;
}

bool TextScanner::end_line(std::string_view field) {
  if (!at_line_end()) {
    std::string_view extra;
    read(extra, field, Within::line);
    return fail(field, "unexpected extra value '" + std::string(extra) + "'");
  }
  skip_line();
  return true;
}

void TextScanner::skip_line() {
  const std::size_t newline = text_.find('\n', position_);
  if (newline == std::string_view::npos) {
    position_ = text_.size();
    return;
  }
  position_ = newline + 1;
  ++line_;
}

bool TextScanner::at_end() {
  skip_spaces(Within::file);
  return position_ == text_.size();
}

bool TextScanner::at_line_end() {
  skip_spaces(Within::line);
  return position_ == text_.size() || text_[position_] == '\n';
}

std::optional<std::string_view> TextScanner::take_until(char stop) {
  const std::size_t found = text_.find(stop, position_);
  const std::size_t end = found == std::string_view::npos ? text_.size() : found;
  const std::string_view taken = text_.substr(position_, end - position_);
  advance(taken.size());
  if (found == std::string_view::npos) return std::nullopt;
  return taken;
}

void TextScanner::advance(std::size_t count) {
  const std::size_t end = std::min(text_.size(), position_ + count);
  for (; position_ < end; ++position_) {
    if (text_[position_] == '\n') ++line_;
  }
}

int TextScanner::line() const {
  if (position_ < text_.size()) return line_;
  // At the end, name the last line that has something on it rather than trailing blank lines.
  int line = line_;
  for (std::size_t i = text_.size(); i > 0 && is_space(text_[i - 1]); --i) {
    if (text_[i - 1] == '\n') --line;
  }
  return std::max(line, 1);
}

bool TextScanner::fail(std::string_view field, std::string message) {
  return fail(Error{.message = std::move(message), .file = path_, .line = line(), .field = std::string(field)});
}

bool TextScanner::fail(Error error) {
  if (!failed_) {
    failed_ = true;
    error_ = std::move(error);
  }
  return false;
}

}  // namespace nav
