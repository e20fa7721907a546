#include "spinewatch/estimator/silhouette/view_coverage.hpp"

#include <vector>

namespace spinewatch {

std::string ViewCoverage::describe() const {
  if (!someone()) return "nobody";
  if (whole()) return "whole";
  std::vector<const char*> cut;
  if (top) cut.push_back("top");
  if (bottom) cut.push_back("bottom");
  if (left) cut.push_back("left");
  if (right) cut.push_back("right");
  std::string s = "cut at";
  for (std::size_t i = 0; i < cut.size(); ++i) s += (i == 0 ? " " : ", ") + std::string(cut[i]);
  return s;
}

ViewCoverage view_coverage(const BitMask& person) {
  ViewCoverage c;
  if (person.empty()) return c;
  c.pixels = person.count();
  if (c.pixels == 0) return c;
  const int last = person.width() - 1;
  for (int y = 0; y < person.height(); ++y) {
    c.left = c.left || person.get(0, y);
    c.right = c.right || person.get(last, y);
  }
  c.top = person.count_row(0) > 0;
  c.bottom = person.count_row(person.height() - 1) > 0;
  return c;
}

}  // namespace spinewatch
