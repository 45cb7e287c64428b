#pragma once
// The one tokenizer shared by every text mesh format (.msh, .vtk, .vtu, .obj): it walks a text
// held in memory token by token, knows the 1-based line of what it read, parses numbers with
// std::from_chars, and turns every failure into a nav::Error naming file, line and field.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "nav/core/error.hpp"

namespace nav {

/// Reads a whole file into memory; an Error (with the path) if it cannot be opened or read.
Result<std::string> read_text_file(const std::string& path);

/// Parses the whole of `token` as a finite double (a leading '+' is accepted).
std::optional<double> parse_double(std::string_view token);

/// Parses the whole of `token` as a decimal integer (a leading '+' is accepted).
std::optional<std::int64_t> parse_int(std::string_view token);

/// The 1-based line on which the token of index `token_index` of `text` starts, `text`
/// starting on line `first_line`; the last line of `text` if there are fewer tokens.
/// Used on error paths to locate a value found faulty after its array was read.
int line_of_token(std::string_view text, int first_line, std::size_t token_index);

/// Whether a read may move on to the next line to find its token.
enum class Within {
  file,  ///< free-form formats: values may be spread over lines (.vtk, .vtu)
  line   ///< record-per-line formats: the value must be on the current line (.msh, .obj)
};

/// A cursor over a text (not owned) that reads whitespace-separated tokens and numbers.
/// Reads return false on failure after recording an Error at the current line; the first
/// Error recorded is kept and returned by error().
class TextScanner {
 public:
  /// Scans `text`, which came from `path` and starts on line `first_line` of that file.
  TextScanner(std::string path, std::string_view text, int first_line = 1);

  /// Reads the next token; fails at the end of the text (or of the line, for Within::line).
  bool read(std::string_view& token, std::string_view field, Within within = Within::file);
  /// Reads the next token as a finite double.
  bool read(double& value, std::string_view field, Within within = Within::file);
  /// Reads the next token as an integer.
  bool read(std::int64_t& value, std::string_view field, Within within = Within::file);
  /// Reads the next token as an integer in [min_value, max_value].
  bool read_in_range(std::int64_t& value, std::int64_t min_value, std::int64_t max_value, std::string_view field,
                     Within within = Within::file);
  /// The next token without consuming it (empty at the end of the text or line).
  std::string_view peek(Within within = Within::file);
  /// Reads the next token and fails unless it equals `word`.
  bool expect(std::string_view word, std::string_view field, Within within = Within::file);

  /// Fails if a token is left on the current line; otherwise moves to the start of the next line.
  bool end_line(std::string_view field);
  /// Moves to the start of the next line, ignoring what is left of the current one.
  void skip_line();
  /// True when only whitespace is left.
  bool at_end();
  /// True when only whitespace is left on the current line.
  bool at_line_end();

  /// The text from the cursor up to (not including) the first `stop`, moving the cursor onto
  /// `stop`; nullopt (cursor at the end) if there is no `stop`.
  std::optional<std::string_view> take_until(char stop);
  /// Moves the cursor over `count` characters (fewer at the end of the text), counting lines.
  void advance(std::size_t count);

  /// The 1-based line of the cursor (at the end of the text: its last line that is not blank).
  int line() const;
  /// Records an Error at the current line (unless one is already recorded) and returns false.
  bool fail(std::string_view field, std::string message);
  /// Records `error` (found elsewhere, e.g. in an array read earlier) unless one is already recorded; returns false.
  bool fail(Error error);
  /// The Error recorded by the first failure.
  const Error& error() const { return error_; }
  /// The file the text came from.
  const std::string& path() const { return path_; }
  /// Characters left after the cursor (a bound for counts read from the file).
  std::size_t remaining() const { return text_.size() - position_; }
  /// The text from offset `start` (an earlier cursor position) to the cursor.
  std::string_view text_since(std::size_t start) const { return text_.substr(start, position_ - start); }
  /// The cursor's offset in the text.
  std::size_t position() const { return position_; }

 private:
  void skip_spaces(Within within);

  std::string path_;
  std::string_view text_;
  std::size_t position_ = 0;
  int line_ = 1;
  bool failed_ = false;
  Error error_;
};

}  // namespace nav
