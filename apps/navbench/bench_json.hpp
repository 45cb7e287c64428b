#pragma once
// The JSON navbench writes, built with nlohmann::json (Debian's nlohmann-json3): records keep
// their fields in the order given, and a file of records holds one record per line.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace navbench {

/// One record or document; fields stay in insertion order.
using Json = nlohmann::ordered_json;

/// Writes `text` to `path`; false, after naming the file on stderr, when it cannot be written.
bool write_output(const std::string& path, const std::string& text);

/// `record` on one line, `"key": value` separated by ", " (values as the library writes them).
std::string one_line(const Json& record);

/// Writes `records` as a JSON array, one record per line; false, after naming the file on
/// stderr, when it cannot be written.
bool write_json_records(const std::string& path, const std::vector<Json>& records);

/// Writes `document` indented by two spaces; false, after naming the file on stderr, when it
/// cannot be written.
bool write_json_document(const std::string& path, const Json& document);

}  // namespace navbench
