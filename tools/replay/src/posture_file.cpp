#include "spinewatch/replay/posture_file.hpp"

#include <fstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "spinewatch/estimator/posture_json.hpp"

namespace spinewatch {

Result<std::vector<Posture>> read_posture_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return Error{fmt::format("{}: cannot be read", path.string())};
  std::vector<Posture> postures;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = fmt::format("{}:{}", path.string(), number);
    const auto json = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (json.is_discarded()) return Error{fmt::format("{}: not valid JSON", where)};
    if (json.is_object() && json.value("class", "") == "hello") continue;
    // Other lines a station writes, given where postures were meant.
    if (json.is_object() && json.value("class", "") == "summary")
      return Error{fmt::format("{}: an exposure summary line: this is a summaries file (replay --summaries, read by "
                               "spinewatch report --summaries), not a posture stream; give the file replay --out wrote",
                               where)};
    auto p = posture_from_json(json, where);
    if (!p) return p.error();
    postures.push_back(std::move(p).value());
  }
  return postures;
}

}  // namespace spinewatch
