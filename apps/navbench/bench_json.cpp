#include "bench_json.hpp"

#include <cstdio>

#include "nav/core/text_file.hpp"

namespace navbench {

std::string one_line(const Json& record) {
  if (!record.is_object()) return record.dump();
  std::string line = "{";
  for (auto field = record.begin(); field != record.end(); ++field) {
    if (field != record.begin()) line += ", ";
    line += Json(field.key()).dump() + ": " + field.value().dump();
  }
  return line + "}";
}

bool write_output(const std::string& path, const std::string& text) {
  const auto written = nav::write_text_file(path, text);
  if (!written.ok()) std::fprintf(stderr, "navbench: %s\n", written.error().describe().c_str());
  return written.ok();
}

bool write_json_records(const std::string& path, const std::vector<Json>& records) {
  std::string text = "[\n";
  for (std::size_t k = 0; k < records.size(); ++k)
    text += "  " + one_line(records[k]) + (k + 1 < records.size() ? ",\n" : "\n");
  return write_output(path, text + "]\n");
}

bool write_json_document(const std::string& path, const Json& document) {
  return write_output(path, document.dump(2) + "\n");
}

}  // namespace navbench
