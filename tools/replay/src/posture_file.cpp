#include "spinewatch/replay/posture_file.hpp"

#include <fstream>

#include <fmt/format.h>

#include "spinewatch/estimator/posture_json.hpp"

namespace spinewatch {

Result<std::vector<Posture>> read_posture_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return Error{fmt::format("{}: cannot be read", path.string())};
  auto lines = decode_posture_stream(in, path.string());
  if (!lines) return lines.error();
  std::vector<Posture> postures;
  postures.reserve(lines->size());
  for (NumberedPosture& line : *lines) postures.push_back(std::move(line.posture));
  return postures;
}

}  // namespace spinewatch
