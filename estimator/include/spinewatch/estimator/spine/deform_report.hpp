#pragma once
// Table 1 of the paper: per-vertebra position errors of a deformed model
// against ground truth (spinewatch deform / eval --deform).
#include <array>
#include <string>
#include <vector>

#include "spinewatch/estimator/posture.hpp"

namespace spinewatch {

struct AxisError {
  double mean = 0, max = 0;  // of absolute values, mm
};

struct LevelError {
  std::string level;
  AxisError lateral, vertical, anterior, distance;  // |ΔZ|, |ΔY|, |ΔX|, |Δ|
};

struct DeformReport {
  std::array<LevelError, kVertebraCount> levels;
  AxisError overall;  // distance over every vertebra of every frame
  std::size_t frames = 0;          // pairs compared
  std::size_t skipped = 0;         // pairs where either side has no vertebrae
};

// Pairs frames by seq when both streams have distinct seqs, else by index.
DeformReport compare_deformation(const std::vector<Posture>& estimated, const std::vector<Posture>& truth);
std::string format_table(const DeformReport& report);

}  // namespace spinewatch
