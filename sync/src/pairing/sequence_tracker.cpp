#include "spinewatch/sync/sequence_tracker.hpp"

#include <algorithm>

namespace spinewatch::sync {

SequenceTracker::Verdict SequenceTracker::observe(std::uint64_t sequence) {
  const auto recent_end = recent_.begin() + static_cast<std::ptrdiff_t>(recent_count_);
  if (std::find(recent_.begin(), recent_end, sequence) != recent_end) return Verdict::Duplicate;
  recent_[recent_next_] = sequence;
  recent_next_ = (recent_next_ + 1) % kRecent;
  recent_count_ = std::min(recent_count_ + 1, kRecent);

  if (!highest_) {
    highest_ = sequence;
  } else if (sequence > *highest_) {
    gaps_ += sequence - *highest_ - 1;
    highest_ = sequence;
  } else if (gaps_ > 0) {
    --gaps_;  // an out-of-order frame filling a gap it had opened
  }
  return Verdict::New;
}

}  // namespace spinewatch::sync
