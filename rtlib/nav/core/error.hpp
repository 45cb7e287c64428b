#pragma once
// Init-time error reporting: a readable error that says what went wrong and where
// (file, line, field). Step-time code never uses these; it reports through HealthFlags.
#include <string>
#include <utility>
#include <variant>

namespace nav {

/// What went wrong at init time, and where: the file, its 1-based line (0 if unknown)
/// and the field or element concerned (empty if none).
struct Error {
  std::string message;
  std::string file{};
  int line = 0;
  std::string field{};

  /// "file:line: field: message", leaving out the parts that are empty.
  std::string describe() const;
};

/// The Error of a check on `field` (no file or line): a build function's refusal.
inline Error field_error(std::string message, std::string field) {
  return Error{.message = std::move(message), .field = std::move(field)};
}

/// The value of an init-time operation or the Error that prevented it.
template <typename T>
class Result {
 public:
  Result(T value) : state_(std::move(value)) {}      // NOLINT: implicit on purpose
  Result(Error error) : state_(std::move(error)) {}  // NOLINT: implicit on purpose

  bool ok() const { return std::holds_alternative<T>(state_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& { return std::get<T>(state_); }
  T& value() & { return std::get<T>(state_); }
  T&& value() && { return std::get<T>(std::move(state_)); }
  const Error& error() const { return std::get<Error>(state_); }

 private:
  std::variant<T, Error> state_;
};

/// Success without a value, or an Error.
struct Done {};
using Status = Result<Done>;

}  // namespace nav
