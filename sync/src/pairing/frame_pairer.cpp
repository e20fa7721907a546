#include "spinewatch/sync/frame_pairer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace spinewatch::sync {
namespace {
constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::min();

std::int64_t abs_diff(std::int64_t a, std::int64_t b) { return a > b ? a - b : b - a; }
}  // namespace

FramePairer::FramePairer(PairerOptions options) : options_(options) {
  const double fps = options_.fps > 0.0 ? options_.fps : 30.0;
  period_ns_ = static_cast<std::int64_t>(std::llround(1e9 / fps));
  tolerance_ns_ = options_.tolerance_ns > 0 ? options_.tolerance_ns : period_ns_ / 2;
  reorder_ns_ = options_.reorder_window_ns >= 0 ? options_.reorder_window_ns : period_ns_;
  options_.max_pending = std::max<std::size_t>(options_.max_pending, 2);
  newest_[0] = newest_[1] = kNever;
}

void FramePairer::insert_sorted(std::deque<Pending>& queue, Pending pending) {
  // Frames nearly always come in order: search from the back.
  auto it = queue.end();
  while (it != queue.begin() && std::prev(it)->t_ns > pending.t_ns) --it;
  queue.insert(it, std::move(pending));
}

void FramePairer::push(View view, Frame frame) {
  const int s = static_cast<int>(index_of(view));
  ++stats_.frames_in[s];
  auto& drops = stats_.drops[s];
  if (sequences_[s].observe(frame.sequence()) == SequenceTracker::Verdict::Duplicate) {
    ++drops.duplicate;
    return;
  }
  drops.sequence_gaps = sequences_[s].gaps();

  const std::int64_t t = frame.timestamp_ns() - (options_.triggered ? options_.frame_latency_ns[s] : 0);
  // Its partner (or its trigger edge) has already been decided without it.
  const auto& horizon = options_.triggered ? decided_trigger_ : decided_until_[s];
  if (horizon && t <= *horizon + (options_.triggered ? tolerance_ns_ : 0)) {
    ++drops.late;
    return;
  }
  newest_[s] = std::max(newest_[s], t);
  insert_sorted(pending_[s], Pending{t, std::move(frame)});

  if (options_.triggered) {
    match_triggered(false);
  } else {
    match_free_run(false);
  }
  // A stalled partner or a stopped trigger must not grow the queue without bound.
  auto& queue = pending_[s];
  while (queue.size() > options_.max_pending) {
    decided_until_[s] = std::max(decided_until_[s].value_or(kNever), queue.front().t_ns);
    queue.pop_front();
    ++drops.overflow;
  }
}

void FramePairer::push_trigger(std::int64_t t_ns) {
  ++stats_.triggers_in;
  if (!options_.triggered) return;
  const bool stale = (decided_trigger_ && t_ns <= *decided_trigger_) ||
                     std::any_of(slots_.begin(), slots_.end(), [&](const Slot& slot) { return slot.t_ns == t_ns; });
  if (stale) {
    ++stats_.triggers_unpaired;
    return;
  }
  auto it = slots_.end();
  while (it != slots_.begin() && std::prev(it)->t_ns > t_ns) --it;
  slots_.insert(it, Slot{t_ns, {}});
  newest_trigger_ = std::max(newest_trigger_.value_or(kNever), t_ns);
  match_triggered(false);
  while (slots_.size() > options_.max_pending) drop_slot_front(true);
}

std::optional<FramePair> FramePairer::pop() {
  if (ready_.empty()) return std::nullopt;
  FramePair pair = std::move(ready_.front());
  ready_.pop_front();
  return pair;
}

void FramePairer::flush() {
  if (options_.triggered) {
    match_triggered(true);
  } else {
    match_free_run(true);
  }
  for (int s = 0; s < 2; ++s) {
    stats_.drops[s].flushed += pending_[s].size();
    for (const auto& p : pending_[s]) decided_until_[s] = std::max(decided_until_[s].value_or(kNever), p.t_ns);
    pending_[s].clear();
  }
}

void FramePairer::emit(std::int64_t t_ns, Frame frontal, Frame lateral) {
  stats_.pair_skew.add(lateral.timestamp_ns() - frontal.timestamp_ns());
  ++stats_.pairs;
  ready_.push_back(FramePair{next_sequence_++, t_ns, std::move(frontal), std::move(lateral)});
}

void FramePairer::match_free_run(bool final) {
  auto& a = pending_[0];
  auto& b = pending_[1];
  while (!a.empty() && !b.empty()) {
    const std::int64_t ta = a.front().t_ns;
    const std::int64_t tb = b.front().t_ns;
    if (abs_diff(ta, tb) <= tolerance_ns_) {
      decided_until_[0] = ta;
      decided_until_[1] = tb;
      emit(ta + (tb - ta) / 2, std::move(a.front().frame), std::move(b.front().frame));
      a.pop_front();
      b.pop_front();
      continue;
    }
    // The older head has no partner among the frames queued; one may still
    // come out of order until the other stream has moved well past it.
    const int older = ta < tb ? 0 : 1;
    const std::int64_t t_old = older == 0 ? ta : tb;
    if (!final && newest_[1 - older] < t_old + tolerance_ns_ + reorder_ns_) break;
    decided_until_[older] = t_old;
    pending_[older].pop_front();
    if (final) {
      ++stats_.drops[older].flushed;
    } else {
      ++stats_.drops[older].unmatched;
    }
  }
}

bool FramePairer::attach_to_slot(int s, Pending& pending) {
  Slot* best = nullptr;
  std::int64_t best_diff = 0;
  for (auto& slot : slots_) {
    const std::int64_t d = abs_diff(slot.t_ns, pending.t_ns);
    if (d <= tolerance_ns_ && (!best || d < best_diff)) {
      best = &slot;
      best_diff = d;
    }
  }
  if (!best) return false;
  if (best->frames[s]) {
    // A second frame on one edge: keep the first, never guess which is right.
    ++stats_.drops[s].unmatched;
    return true;
  }
  stats_.trigger_skew[s].add(pending.t_ns - best->t_ns);
  best->frames[s] = std::move(pending.frame);
  return true;
}

void FramePairer::drop_slot_front(bool overflow) {
  Slot& slot = slots_.front();
  bool any = false;
  for (int s = 0; s < 2; ++s) {
    if (!slot.frames[s]) continue;
    any = true;
    if (overflow) {
      ++stats_.drops[s].overflow;
    } else {
      ++stats_.drops[s].unmatched;
    }
  }
  ++stats_.triggers_unpaired;
  if (overflow && !any) ++stats_.triggers_overflow;
  decided_trigger_ = slot.t_ns;
  slots_.pop_front();
}

void FramePairer::match_triggered(bool final) {
  for (int s = 0; s < 2; ++s) {
    auto& q = pending_[s];
    for (auto it = q.begin(); it != q.end();) {
      if (attach_to_slot(s, *it)) {
        it = q.erase(it);
        continue;
      }
      // No edge near it; one may still come until the trigger has moved on.
      const bool trigger_moved_on = newest_trigger_ && *newest_trigger_ >= it->t_ns + tolerance_ns_ + reorder_ns_;
      if (trigger_moved_on && !final) {
        ++stats_.drops[s].unmatched;
        it = q.erase(it);
        continue;
      }
      ++it;
    }
  }
  while (!slots_.empty()) {
    Slot& head = slots_.front();
    if (head.frames[0] && head.frames[1]) {
      decided_trigger_ = head.t_ns;
      emit(head.t_ns, std::move(*head.frames[0]), std::move(*head.frames[1]));
      slots_.pop_front();
      continue;
    }
    bool dead = true;
    for (int s = 0; s < 2; ++s) {
      if (!head.frames[s] && newest_[s] < head.t_ns + tolerance_ns_ + reorder_ns_) dead = false;
    }
    if (final) {
      for (int s = 0; s < 2; ++s) {
        if (head.frames[s]) ++stats_.drops[s].flushed;
        head.frames[s].reset();
      }
      dead = true;
    }
    if (!dead) break;
    drop_slot_front(false);
  }
}

}  // namespace spinewatch::sync
