#pragma once
// Driver sequence numbers of one stream: duplicates, and gaps (frames the
// driver never delivered). Tolerates frames arriving slightly out of order:
// a late frame fills the gap it had opened.
#include <array>
#include <cstdint>
#include <optional>

namespace spinewatch::sync {

class SequenceTracker {
 public:
  enum class Verdict { New, Duplicate };
  Verdict observe(std::uint64_t sequence);
  std::uint64_t gaps() const { return gaps_; }

 private:
  static constexpr std::size_t kRecent = 64;  // sequence numbers remembered for duplicates
  std::array<std::uint64_t, kRecent> recent_{};
  std::size_t recent_count_ = 0;
  std::size_t recent_next_ = 0;
  std::optional<std::uint64_t> highest_;
  std::uint64_t gaps_ = 0;
};

}  // namespace spinewatch::sync
